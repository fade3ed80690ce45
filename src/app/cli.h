// Command-line parsing shared by the subcommands.
#pragma once

#include <functional>
#include <limits>
#include <string>
#include <vector>

namespace tissu {

// The next argument, as the value of the option being read; throws UsageError
// "<command>: <option> needs a value" when there is none.
using OptionValue = std::function<const std::string&()>;

// Walks a subcommand's arguments (after its name). "--help" or "-h" prints `help` and
// returns false. Every other argument goes to take(argument, value), which returns false
// for one it does not know: a UsageError "<command>: unknown option ARG (see <command>
// --help)" when ARG starts with '-', else "<command>: unexpected argument \"ARG\"".
bool walk_arguments(const std::vector<std::string>& args, const std::string& command,
                    const char* help,
                    const std::function<bool(const std::string&, const OptionValue&)>& take);

// `text` as an integer in [min, max]; InputError "<option>: expected ..." otherwise.
long long parse_count(const std::string& option, const std::string& text, long long min,
                      long long max = std::numeric_limits<long long>::max());

constexpr int kMaxThreads = 256;

// Options common to the commands that run a scene.
struct SceneCommandOptions {
  std::string scene_file;
  std::string out_dir;  // default: out/<scene file stem>
  std::vector<std::string> overrides;
  std::string report_path;  // default: <out_dir>/report.json
  int obj_every = 0;
  int threads = 0;  // simulation threads; 0 = the processors available
  bool quiet = false;
  bool check = false;  // exact crossing check of every recorded frame
  bool overwrite = false;  // -y: replace an earlier run's outputs (app/earlier_outputs.h)
  // render-only options
  bool png = false;
  bool mp4 = true;
  long long max_frames = -1;
  int stills = 0;  // PNG stills spread over the run
};

// Parses `args` (after the subcommand name). `render` enables --png, --no-mp4, --frames.
// Throws InputError on bad usage; returns false when --help was printed.
bool parse_scene_command(const std::vector<std::string>& args, bool render,
                         SceneCommandOptions& out);

// Creates `dir` (and parents) and checks it can be written; OutputError (exit code 1)
// otherwise.
void prepare_output_dir(const std::string& dir);

// Output directories of one run, created with prepare_output_dir. It remembers the
// directories it created itself (not those that existed), so a run that fails before it
// has written anything (one output location cannot be created) leaves no empty directory.
class OutputDirs {
 public:
  void prepare(const std::string& dir);
  // Removes the directories this object created that are still empty, deepest first.
  void remove_created_if_empty() noexcept;

 private:
  std::vector<std::string> created_;  // in creation order: parents first
};

}  // namespace tissu
