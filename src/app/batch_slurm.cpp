#include "app/batch_slurm.h"

#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <ostream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "app/batch_gather.h"
#include "app/batch_job.h"
#include "app/report.h"
#include "core/error.h"

namespace tissu {

namespace {

namespace fs = std::filesystem;

// Scheduler commands retry for minutes when slurmctld is down: each gets a deadline.
constexpr const char* kCommandTimeout = "timeout 120 ";

struct CommandResult {
  int exit_code = -1;
  std::string out, err;
};

CommandResult run_command(const std::string& command, const fs::path& err_file) {
  CommandResult r;
  FILE* pipe = ::popen((command + " 2>" + shell_quote(err_file.string())).c_str(), "r");
  if (!pipe) return r;
  char buffer[4096];
  size_t n = 0;
  while ((n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0) r.out.append(buffer, n);
  const int status = ::pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::ifstream in(err_file);
  std::stringstream ss;
  ss << in.rdbuf();
  r.err = ss.str();
  while (!r.err.empty() && (r.err.back() == '\n' || r.err.back() == '\r')) r.err.pop_back();
  return r;
}

std::string trimmed(std::string s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.pop_back();
  return s;
}

// A value in an #SBATCH line: sbatch splits those lines at spaces unless quoted.
std::string directive_quote(const std::string& value) {
  if (value.find_first_of(" \t\"'") == std::string::npos) return value;
  std::string out = "\"";
  for (char c : value) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

void add_resources(std::ostream& script, const SlurmResources& r, bool per_task) {
  if (per_task) script << "#SBATCH --cpus-per-task=" << r.cpus_per_task << "\n";
  if (per_task && !r.mem.empty()) script << "#SBATCH --mem=" << r.mem << "\n";
  if (!r.time.empty()) script << "#SBATCH --time=" << r.time << "\n";
  if (!r.partition.empty()) script << "#SBATCH --partition=" << r.partition << "\n";
  if (!r.account.empty()) script << "#SBATCH --account=" << r.account << "\n";
  for (const std::string& e : r.extra) script << "#SBATCH " << e << "\n";
}

std::string write_script(const BatchPlan& plan, const std::string& name, const std::string& body,
                         const std::string& output, bool per_task) {
  std::ostringstream s;
  s << "#!/bin/sh\n"
    << "# Written by `tissu batch --executor slurm` for " << plan.batch_file << ".\n"
    << "#SBATCH --job-name=" << directive_quote("tissu-" + plan.name + (per_task ? "" : "-gather")) << "\n"
    << "#SBATCH --output=" << directive_quote(output) << "\n";
  add_resources(s, plan.slurm, per_task);
  s << body;
  const std::string path = (fs::path(plan.dir) / "slurm" / name).string();
  write_text_file(path, s.str());
  fs::permissions(path, fs::perms::owner_exec | fs::perms::group_exec | fs::perms::others_exec,
                  fs::perm_options::add);
  return path;
}

// sbatch --parsable prints "ID" or "ID;CLUSTER".
std::string submit(const std::string& options, const std::string& script, const fs::path& err) {
  const CommandResult r = run_command(std::string(kCommandTimeout) + "sbatch --parsable " + options +
                                          " " + shell_quote(script),
                                      err);
  const std::string id = trimmed(r.out.substr(0, r.out.find(';')));
  if (r.exit_code != 0 || id.empty()) {
    const std::string why = r.exit_code == 124 ? "no answer within 120 s"
                            : r.err.empty()    ? "exit code " + std::to_string(r.exit_code)
                                               : r.err.substr(r.err.rfind('\n') + 1);
    throw OutputError("sbatch " + script + ": " + why);
  }
  return id;
}

}  // namespace

std::string index_ranges(const std::vector<size_t>& indices) {
  std::string out;
  for (size_t i = 0; i < indices.size();) {
    size_t j = i;
    while (j + 1 < indices.size() && indices[j + 1] == indices[j] + 1) ++j;
    if (!out.empty()) out += ",";
    out += std::to_string(indices[i]);
    if (j > i) out += "-" + std::to_string(indices[j]);
    i = j + 1;
  }
  return out;
}

SlurmSubmission submit_to_slurm(const BatchPlan& plan, const std::vector<size_t>& todo) {
  const fs::path slurm_dir = fs::path(plan.dir) / "slurm";
  fs::create_directories(slurm_dir);
  const std::string program = shell_quote(tissu_program());
  const std::string dir = shell_quote(plan.dir);
  SlurmSubmission s;
  const fs::path err = slurm_dir / "sbatch.err";
  if (!todo.empty()) {
    const std::string array = write_script(
        plan, "array.sh",
        "exec " + program + " batch job " + dir + " --index \"$SLURM_ARRAY_TASK_ID\"\n",
        (slurm_dir / "task-%a.out").string(), true);
    s.array_job = submit("--array=" + index_ranges(todo), array, err);
    for (size_t i : todo) {
      JobState queued;
      queued.status = "queued";
      queued.executor = "slurm";
      write_job_state(plan, i, queued);
    }
  }
  const std::string gather = write_script(plan, "gather.sh",
                                          "exec " + program + " batch gather " + dir + "\n",
                                          (slurm_dir / "gather.out").string(), false);
  s.gather_job = submit(s.array_job.empty() ? "" : "--dependency=afterany:" + s.array_job, gather, err);
  const nlohmann::ordered_json record = {{"array_job", s.array_job},
                                         {"gather_job", s.gather_job},
                                         {"indices", todo},
                                         {"submitted", utc_now()}};
  write_text_file((slurm_dir / "submitted.json").string(), record.dump(1) + "\n");
  return s;
}

namespace {

// The last submission recorded in DIR/slurm/submitted.json and what squeue says of it.
struct SchedulerView {
  std::string array_job, gather_job;       // "" when never submitted
  std::map<std::string, std::string> jobs;  // "123_4" or "124" -> PENDING, RUNNING, ...
  std::string note;                         // why squeue could not tell, if it could not
};

SchedulerView scheduler_view(const BatchPlan& plan) {
  const fs::path slurm_dir = fs::path(plan.dir) / "slurm";
  SchedulerView view;
  const std::optional<nlohmann::json> submitted = read_json_file(slurm_dir / "submitted.json");
  if (!submitted || !submitted->is_object()) return view;
  const nlohmann::json& record = *submitted;
  view.array_job = record.value("array_job", "");
  view.gather_job = record.value("gather_job", "");
  if (view.gather_job.empty()) return view;
  const std::string ids = view.array_job.empty() ? view.gather_job : view.array_job + "," + view.gather_job;
  const CommandResult r = run_command(std::string(kCommandTimeout) + "squeue -h -r -o '%i|%T' -j " + ids,
                                      slurm_dir / "squeue.err");
  if (r.exit_code != 0) {
    view.note = "squeue failed: " + (r.err.empty() ? "exit code " + std::to_string(r.exit_code) : r.err);
  }
  std::istringstream lines(r.out);
  for (std::string line; std::getline(lines, line);) {
    const size_t bar = line.find('|');
    if (bar != std::string::npos) view.jobs[trimmed(line.substr(0, bar))] = trimmed(line.substr(bar + 1));
  }
  return view;
}

}  // namespace

void refuse_while_queued(const BatchPlan& plan) {
  const SchedulerView view = scheduler_view(plan);
  if (view.jobs.empty()) return;
  throw InputError(plan.dir + ": this batch is still queued or running on Slurm (array job " +
                   (view.array_job.empty() ? "-" : view.array_job) + ", gathering job " +
                   view.gather_job + "); wait for it (tissu batch status) or scancel it first");
}

int print_batch_status(const BatchPlan& plan, std::ostream& out) {
  SchedulerView view = scheduler_view(plan);
  std::map<std::string, std::string>& scheduler = view.jobs;
  const std::string& array_job = view.array_job;
  const std::string& gather_job = view.gather_job;
  const std::string& scheduler_note = view.note;
  out << "batch " << plan.name << " (" << plan.dir << "): " << plan.jobs.size() << " jobs\n";
  if (!gather_job.empty()) {
    out << "slurm: array job " << (array_job.empty() ? "-" : array_job) << ", gathering job "
        << gather_job << " "
        << (scheduler.count(gather_job) ? scheduler[gather_job] : "(no longer queued)") << "\n";
  }
  if (!scheduler_note.empty()) out << "slurm: " << scheduler_note << "\n";
  std::map<std::string, int> counts;
  for (size_t i = 0; i < plan.jobs.size(); ++i) {
    const JobState s = read_job_state(plan, i);
    ++counts[s.status];
    out << plan.jobs[i].name << "  " << s.status;
    const std::string task = array_job + "_" + std::to_string(i);
    if (!array_job.empty() && scheduler.count(task)) out << "  slurm " << scheduler[task];
    if (s.status == "done" || s.status == "failed" || s.status == "interrupted") {
      char wall[32];
      std::snprintf(wall, sizeof wall, "%.1f", s.wall_s);
      out << "  exit " << s.exit_code << "  " << wall << " s";
    }
    if (!s.error.empty()) out << "  " << s.error;
    out << "\n";
  }
  bool first = true;
  for (const auto& [status, n] : counts) {
    out << (first ? "" : ", ") << n << " " << status;
    first = false;
  }
  out << "\n";
  return 0;
}

}  // namespace tissu
