// A batch's output directory: DIR/batch.json (the plan: every job's name, overrides and
// tissu arguments, and the hash of the batch file), DIR/jobs/<name>/ (the job's outputs,
// its log.txt and its state.json). Executors and the gathering step work from the plan
// alone, so a cluster node needs only DIR and the tissu program.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "app/batch_spec.h"
#include "core/utc_time.h"

namespace tissu {

struct PlannedJob {
  std::string name;
  std::vector<std::string> overrides;  // "key=value", as given to --set
  std::vector<std::string> args;       // tissu arguments after the program name
};

struct BatchPlan {
  std::string dir;
  std::string batch_file;
  std::string name;
  std::string hash;
  std::string produce;
  int stills = 0;
  SlurmResources slurm;
  std::vector<PlannedJob> jobs;

  std::string job_dir(size_t i) const;
  std::string plan_path() const;
};

// The plan of `batch` in `dir`. Writes nothing.
BatchPlan plan_batch(const BatchSpec& batch, const std::string& dir);

// Makes `plan.dir` the batch's directory: creates it, or accepts it when it holds the
// same batch (same hash); refuses (InputError naming the directory) one that holds
// another batch, or files that are not a batch's. Writes DIR/batch.json and the job
// directories.
void claim_batch_dir(const BatchPlan& plan);

// An exclusive lock on DIR/.lock (flock), held while one tissu batch runs or submits
// there, so two at once never run the same job. The system drops it when the process ends,
// however it ends.
class BatchDirLock {
 public:
  // InputError naming DIR (and the holder's process id) when another process holds it.
  explicit BatchDirLock(const BatchPlan& plan);
  ~BatchDirLock();
  BatchDirLock(const BatchDirLock&) = delete;
  BatchDirLock& operator=(const BatchDirLock&) = delete;

 private:
  int fd_ = -1;
};

// Reads DIR/batch.json; InputError when DIR is not a batch directory.
BatchPlan read_batch_plan(const std::string& dir);

// What a job's state.json says.
struct JobState {
  std::string status = "pending";  // pending, queued, running, done, failed, interrupted
  int exit_code = -1;
  std::string error;     // the job's last error line, for failed jobs
  std::string started;   // UTC, ISO 8601
  std::string finished;
  double wall_s = 0;
  std::string host;
  std::string executor;  // local, slurm
};

JobState read_job_state(const BatchPlan& plan, size_t i);  // "pending" when absent or unreadable
void write_job_state(const BatchPlan& plan, size_t i, const JobState& state);

// True when the job is done and its outputs are complete and valid: state "done", a
// readable report.json with status ok or stopped, and the stills (and MP4) asked for;
// for a figure job, figure.png and its report; for a study, study.csv, .md and .png.
bool job_complete(const BatchPlan& plan, size_t i);

std::string utc_now();   // "2026-11-25T15:02:53Z"
// The JSON document in `path`; nullopt when it is missing or not valid JSON (a job's
// state, report or the scheduler's record may be absent or cut short).
std::optional<nlohmann::json> read_json_file(const std::filesystem::path& path);
std::string host_name();

}  // namespace tissu
