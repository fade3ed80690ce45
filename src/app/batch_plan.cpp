#include "app/batch_plan.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>

#include <ctime>
#include <filesystem>
#include <fstream>
#include <optional>

#include <nlohmann/json.hpp>

#include "app/cli.h"
#include "app/report.h"
#include "core/error.h"
#include "core/partial_file.h"

namespace tissu {

namespace {

namespace fs = std::filesystem;
using Ordered = nlohmann::ordered_json;

Ordered plan_json(const BatchPlan& plan) {
  Ordered jobs = Ordered::array();
  for (const PlannedJob& j : plan.jobs) {
    jobs.push_back({{"name", j.name}, {"overrides", j.overrides}, {"args", j.args}});
  }
  const SlurmResources& s = plan.slurm;
  return {{"batch_file", plan.batch_file}, {"name", plan.name}, {"hash", plan.hash},
          {"produce", plan.produce}, {"stills", plan.stills},
          {"slurm", {{"cpus_per_task", s.cpus_per_task}, {"mem", s.mem}, {"time", s.time},
                     {"partition", s.partition}, {"account", s.account}, {"sbatch", s.extra}}},
          {"jobs", jobs}};
}

}  // namespace

std::optional<nlohmann::json> read_json_file(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) return std::nullopt;
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception&) {
    return std::nullopt;
  }
}

std::string BatchPlan::job_dir(size_t i) const {
  return (fs::path(dir) / "jobs" / jobs.at(i).name).string();
}

std::string BatchPlan::plan_path() const { return (fs::path(dir) / "batch.json").string(); }

BatchPlan plan_batch(const BatchSpec& batch, const std::string& dir) {
  BatchPlan plan;
  plan.dir = fs::absolute(dir).lexically_normal().string();
  if (plan.dir.size() > 1 && plan.dir.back() == '/') plan.dir.pop_back();
  plan.batch_file = fs::absolute(batch.file).lexically_normal().string();
  plan.name = batch.name;
  plan.hash = batch.hash;
  plan.produce = batch.produce;
  plan.stills = batch.stills;
  plan.slurm = batch.slurm;
  for (const BatchJob& job : batch.jobs) {
    PlannedJob p;
    p.name = job.name;
    for (const JobOverride& o : job.overrides) p.overrides.push_back(o.assignment());
    plan.jobs.push_back(p);
  }
  for (size_t i = 0; i < plan.jobs.size(); ++i) {
    plan.jobs[i].args = job_arguments(batch, batch.jobs[i], plan.job_dir(i));
  }
  return plan;
}

void claim_batch_dir(const BatchPlan& plan) {
  std::error_code ec;
  const fs::path stamp = plan.plan_path();
  if (fs::exists(stamp, ec)) {
    const auto earlier = read_json_file(stamp);
    const std::string hash = earlier && earlier->contains("hash") && (*earlier)["hash"].is_string()
                                 ? (*earlier)["hash"].get<std::string>()
                                 : "";
    if (hash != plan.hash) {
      const std::string other = earlier && earlier->value("batch_file", "") != ""
                                    ? (*earlier)["batch_file"].get<std::string>()
                                    : "an unreadable batch.json";
      throw InputError(plan.dir + ": holds the outputs of another batch (" + other +
                       "); give another --out directory, or remove this one");
    }
  } else if (fs::exists(plan.dir, ec) && !(fs::is_directory(plan.dir, ec) && fs::is_empty(plan.dir, ec))) {
    throw InputError(plan.dir + ": exists and is not a batch directory (no batch.json); "
                     "give a new or empty --out directory");
  }
  prepare_output_dir(plan.dir);
  for (size_t i = 0; i < plan.jobs.size(); ++i) prepare_output_dir(plan.job_dir(i));
  write_text_file(plan.plan_path(), plan_json(plan).dump(1) + "\n");
}

BatchDirLock::BatchDirLock(const BatchPlan& plan) {
  const std::string path = (fs::path(plan.dir) / ".lock").string();
  fd_ = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0) throw OutputError(path + ": cannot open: " + errno_text(errno));
  if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    char holder[32] = {};
    const ssize_t n = ::pread(fd_, holder, sizeof holder - 1, 0);
    ::close(fd_);
    fd_ = -1;
    const std::string pid = n > 0 ? std::string(holder, static_cast<size_t>(n)) : "";
    throw InputError(plan.dir + ": another tissu batch runs in this directory" +
                     (pid.empty() ? std::string() : " (process " + pid + ")") +
                     "; wait for it or stop it first");
  }
  const std::string pid = std::to_string(::getpid());
  if (::ftruncate(fd_, 0) == 0) {
    const ssize_t ignored = ::pwrite(fd_, pid.data(), pid.size(), 0);
    (void)ignored;
  }
}

BatchDirLock::~BatchDirLock() {
  if (fd_ >= 0) ::close(fd_);  // closing releases the lock
}

BatchPlan read_batch_plan(const std::string& dir) {
  BatchPlan plan;
  plan.dir = fs::absolute(dir).lexically_normal().string();
  if (plan.dir.size() > 1 && plan.dir.back() == '/') plan.dir.pop_back();
  const auto doc = read_json_file(plan.plan_path());
  if (!doc) throw InputError(plan.dir + ": not a batch directory (no readable batch.json)");
  try {
    plan.batch_file = doc->at("batch_file").get<std::string>();
    plan.name = doc->at("name").get<std::string>();
    plan.hash = doc->at("hash").get<std::string>();
    plan.produce = doc->at("produce").get<std::string>();
    plan.stills = doc->at("stills").get<int>();
    const auto& s = doc->at("slurm");
    plan.slurm.cpus_per_task = s.at("cpus_per_task").get<int>();
    plan.slurm.mem = s.at("mem").get<std::string>();
    plan.slurm.time = s.at("time").get<std::string>();
    plan.slurm.partition = s.at("partition").get<std::string>();
    plan.slurm.account = s.at("account").get<std::string>();
    plan.slurm.extra = s.at("sbatch").get<std::vector<std::string>>();
    for (const auto& j : doc->at("jobs")) {
      plan.jobs.push_back({j.at("name").get<std::string>(),
                           j.at("overrides").get<std::vector<std::string>>(),
                           j.at("args").get<std::vector<std::string>>()});
    }
  } catch (const nlohmann::json::exception& e) {
    throw InputError(plan.plan_path() + ": not a batch plan: " + e.what());
  }
  return plan;
}

JobState read_job_state(const BatchPlan& plan, size_t i) {
  JobState s;
  const auto doc = read_json_file(fs::path(plan.job_dir(i)) / "state.json");
  if (!doc || !doc->is_object()) return s;
  s.status = doc->value("status", "pending");
  s.exit_code = doc->value("exit_code", -1);
  s.error = doc->value("error", "");
  s.started = doc->value("started", "");
  s.finished = doc->value("finished", "");
  s.wall_s = doc->value("wall_s", 0.0);
  s.host = doc->value("host", "");
  s.executor = doc->value("executor", "");
  return s;
}

void write_job_state(const BatchPlan& plan, size_t i, const JobState& s) {
  const Ordered doc = {{"job", plan.jobs.at(i).name}, {"status", s.status},
                       {"exit_code", s.exit_code},    {"error", s.error},
                       {"started", s.started},        {"finished", s.finished},
                       {"wall_s", s.wall_s},          {"host", s.host},
                       {"executor", s.executor},      {"batch_hash", plan.hash}};
  write_text_file((fs::path(plan.job_dir(i)) / "state.json").string(), doc.dump(1) + "\n");
}

bool job_complete(const BatchPlan& plan, size_t i) {
  if (read_job_state(plan, i).status != "done") return false;
  const fs::path dir = plan.job_dir(i);
  std::error_code ec;
  if (plan.produce == "figure") {
    return fs::is_regular_file(dir / "figure.png", ec) && fs::is_regular_file(dir / "figure.report.json", ec);
  }
  if (plan.produce == "paper") {
    for (const char* f : {"paper-results.md", "paper-results.csv"}) {
      if (!fs::is_regular_file(dir / f, ec)) return false;
    }
    return true;
  }
  if (plan.produce == "study") {
    for (const char* f : {"study.csv", "study.md", "study.png"}) {
      if (!fs::is_regular_file(dir / f, ec)) return false;
    }
    return true;
  }
  const auto report = read_json_file(dir / "report.json");
  if (!report || !report->is_object()) return false;
  const std::string status = report->value("status", "");
  if (status != "ok" && status != "stopped") return false;
  if (plan.stills > 0) {
    int stills = 0;
    for (const auto& e : fs::directory_iterator(dir / "stills", ec)) {
      if (e.path().extension() == ".png") ++stills;
    }
    if (stills < plan.stills) return false;
  }
  if (plan.produce == "render") {
    bool mp4 = false;
    for (const auto& e : fs::directory_iterator(dir, ec)) mp4 |= e.path().extension() == ".mp4";
    if (!mp4) return false;
  }
  return true;
}

std::string utc_now() { return utc_now("%Y-%m-%dT%H:%M:%SZ"); }

std::string host_name() {
  char name[256] = {};
  if (gethostname(name, sizeof name - 1) != 0) return "";
  return name;
}

}  // namespace tissu
