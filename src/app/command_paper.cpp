// tissu paper: runs the experiments of the paper's section 4 and writes
// DIR/paper-results.md and DIR/paper-results.csv (see src/study/paper/paper_experiments.h).
#include <algorithm>
#include <iostream>
#include <sstream>

#include "app/cli.h"
#include "app/commands.h"
#include "core/error.h"
#include "study/paper/paper_experiments.h"

namespace tissu {

namespace {

const char* kUsage =
    "usage: tissu paper [--scenes DIR] [--out DIR] [--experiments LIST] [--repeats N] [--quick] [--quiet]\n"
    "Runs the experiments of the paper's section 4 on this machine and writes\n"
    "DIR/paper-results.md and DIR/paper-results.csv: time of 2000 iterations on Tissu 1 and\n"
    "Tissu 2 next to the paper's, divergence without position correction (and how it moves\n"
    "with the time step, stiffness and correction settings), distance from a converged\n"
    "reference, free fall, and the cloth hung at 3 points. Takes a few minutes.\n"
    "  --scenes DIR   the paper scenes (default scenes/paper)\n"
    "  --out DIR      where to write (default out/paper; docs/ holds the published run)\n"
    "  --experiments LIST  comma-separated: timing, divergence, accuracy, hung (default all);\n"
    "                 a batch runs each as a job of its own (docs/batch.md)\n"
    "  --repeats N    timed runs per case; fastest and median reported (default 5)\n"
    "  --quick        fewer iterations and cells: checks the command, not the results\n"
    "  --quiet        no progress lines\n"
    "Exit codes: 0 ok, 1 output error, 2 bad input.\n";

}  // namespace

int command_paper(const std::vector<std::string>& args) {
  PaperOptions o;
  bool quiet = false;
  o.command_line = "tissu paper";
  const bool go = walk_arguments(args, "tissu paper", kUsage, [&](const std::string& a,
                                                                  const OptionValue& value) {
    // The command line as given goes into the results file; --quiet changes nothing there.
    auto recorded = [&]() -> const std::string& {
      const std::string& v = value();
      o.command_line += " " + a + " " + v;
      return v;
    };
    if (a == "--scenes") {
      o.scenes_dir = recorded();
    } else if (a == "--out") {
      o.out_dir = recorded();
    } else if (a == "--experiments") {
      std::stringstream list(recorded());
      std::string name;
      const std::vector<std::string> names = paper_experiment_names();
      while (std::getline(list, name, ',')) {
        if (std::find(names.begin(), names.end(), name) == names.end()) {
          throw UsageError("tissu paper: --experiments: unknown experiment \"" + name +
                           "\" (timing, divergence, accuracy, hung)");
        }
        o.experiments.push_back(name);
      }
    } else if (a == "--repeats") {
      const std::string v = recorded();
      try {
        size_t used = 0;
        o.repeats = std::stoi(v, &used);
        if (used != v.size() || o.repeats < 1 || o.repeats > 100) throw std::invalid_argument(v);
      } catch (const std::exception&) {
        throw UsageError("tissu paper: --repeats must be an integer in 1..100, got " + v);
      }
    } else if (a == "--quick") {
      o.quick = true;
      o.command_line += " " + a;
    } else if (a == "--quiet") {
      quiet = true;
    } else {
      throw UsageError("tissu paper: unknown argument " + a + " (see tissu paper --help)");
    }
    return true;
  });
  if (!go) return kExitOk;
  prepare_output_dir(o.out_dir);
  if (!quiet) o.log = [](const std::string& line) { std::cerr << "tissu: paper: " << line << "\n"; };
  const auto [md, csv] = run_paper_experiments(o);
  if (!quiet) std::cerr << "tissu: wrote " << md << " and " << csv << "\n";
  return kExitOk;
}

}  // namespace tissu
