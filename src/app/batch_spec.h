// A batch file: one base scene and a grid or a list of overrides (or a list of scene
// files), and what to produce for each job. docs/batch.md describes the format.
#pragma once

#include <nlohmann/json.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace tissu {

// One `--set KEY=VALUE` override of a job, kept as the key and the JSON value.
struct JobOverride {
  std::string key;
  nlohmann::json value;
  std::string assignment() const;  // "cloth.material=silk"
};

struct BatchJob {
  std::string name;        // the directory name under DIR/jobs/, unique in the batch
  std::string scene_file;  // absolute (the figure file of a "figure" job)
  std::vector<JobOverride> overrides;  // the batch's own, then the job's
};

// Resources each task asks Slurm for (sbatch options; empty: the cluster's default).
struct SlurmResources {
  int cpus_per_task = 1;
  std::string mem;        // --mem, e.g. "1G"
  std::string time;       // --time, e.g. "00:30:00"
  std::string partition;  // --partition
  std::string account;    // --account
  std::vector<std::string> extra;  // further sbatch options, as given
};

struct BatchSpec {
  std::string file;  // the batch file as given
  std::string name;  // "name", else the file's stem
  // "run", "render" (MP4), "stills" (no MP4), "figure" (tissu figure of a figure file) or
  // "study" (tissu study: error against cost of every integrator)
  std::string produce = "render";
  std::vector<std::string> options;  // further options of each job's command, as given
  int stills = 0;                  // stills per job (render, stills)
  long long frames = 0;            // --frames N for render; 0 = every frame
  int threads = 1;                 // --threads of each job
  SlurmResources slurm;
  std::vector<BatchJob> jobs;
  std::string hash;  // of the batch as read (hex), for refusing a different batch in DIR
};

// Reads and checks a batch file. Errors are InputError "FILE: json.path: problem".
BatchSpec read_batch_file(const std::string& file);

// The tissu arguments (after the program name) that produce `job` in `job_dir`.
std::vector<std::string> job_arguments(const BatchSpec& batch, const BatchJob& job,
                                       const std::string& job_dir);

// A directory name for a set of overrides: "material-silk_dt-0.0001" (the last part of
// each key, then the value; characters other than letters, digits, '.', '_', '+' and
// '-' become '-').
std::string job_name_of(const std::vector<JobOverride>& overrides);

// 64-bit FNV-1a of `text`, as 16 hex digits.
std::string fnv1a_hex(const std::string& text);

}  // namespace tissu
