#include "app/batch_job.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <vector>

#include "app/commands.h"
#include "core/cpu_clock.h"
#include "core/error.h"
#include "core/executable_dir.h"
#include "core/partial_file.h"

extern char** environ;

namespace tissu {

namespace {

namespace fs = std::filesystem;

std::string log_path(const BatchPlan& plan, size_t i) {
  return (fs::path(plan.job_dir(i)) / "log.txt").string();
}

// Why the child failed, as it printed it: the line that says where it diverged (a
// divergence is followed by a hint line), else the last line of the log that is not empty.
std::string last_log_line(const std::string& path) {
  std::ifstream in(path);
  std::string line, last, diverged;
  while (std::getline(in, line)) {
    if (line.find_first_not_of(" \t\r") != std::string::npos) last = line;
    if (line.find(": diverged at step ") != std::string::npos) diverged = line;
  }
  if (!diverged.empty()) last = diverged;
  const size_t cr = last.rfind('\r');  // a progress line redrawn in place
  if (cr != std::string::npos) last = last.substr(cr + 1);
  const std::string prefix = "tissu: ";
  return last.rfind(prefix, 0) == 0 ? last.substr(prefix.size()) : last;
}

}  // namespace

std::string tissu_program() {
  std::vector<char> buffer(4096);
  const ssize_t n = readlink("/proc/self/exe", buffer.data(), buffer.size() - 1);
  if (n <= 0) throw OutputError("cannot find the tissu program (/proc/self/exe)");
  return std::string(buffer.data(), static_cast<size_t>(n));
}

pid_t start_job(const BatchPlan& plan, size_t i, const std::string& executor) {
  JobState state;
  state.status = "running";
  state.started = utc_now();
  state.host = host_name();
  state.executor = executor;
  write_job_state(plan, i, state);

  const std::string log = log_path(plan, i);
  const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw OutputError(log + ": cannot write: " + errno_text(errno));
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_adddup2(&actions, fd, STDOUT_FILENO);
  posix_spawn_file_actions_adddup2(&actions, fd, STDERR_FILENO);

  const std::string program = tissu_program();
  std::vector<std::string> args{program};
  args.insert(args.end(), plan.jobs[i].args.begin(), plan.jobs[i].args.end());
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  const int error = posix_spawn(&pid, program.c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  ::close(fd);
  if (error != 0) throw OutputError(program + ": cannot start a job: " + errno_text(error));
  return pid;
}

JobState finish_job(const BatchPlan& plan, size_t i, int wait_status, double wall_s) {
  JobState state = read_job_state(plan, i);
  state.finished = utc_now();
  state.wall_s = wall_s;
  if (WIFEXITED(wait_status)) {
    state.exit_code = WEXITSTATUS(wait_status);
    state.status = state.exit_code == 0                  ? "done"
                   : state.exit_code == kExitInterrupted ? "interrupted"
                                                         : "failed";
  } else {
    const int sig = WIFSIGNALED(wait_status) ? WTERMSIG(wait_status) : 0;
    state.exit_code = 128 + sig;
    state.status = sig == SIGINT || sig == SIGTERM ? "interrupted" : "failed";
    state.error = std::string("killed by signal ") + std::to_string(sig);
  }
  if (state.status != "done" && state.error.empty()) {
    state.error = last_log_line(log_path(plan, i));
    if (state.error.empty()) state.error = "exit code " + std::to_string(state.exit_code);
  }
  if (state.status == "done") state.error.clear();
  write_job_state(plan, i, state);
  return state;
}

JobState run_job_here(const BatchPlan& plan, size_t i, const std::string& executor) {
  const double start = wall_seconds();
  const pid_t pid = start_job(plan, i, executor);
  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) throw OutputError("cannot wait for job " + plan.jobs[i].name + ": " + errno_text(errno));
  }
  return finish_job(plan, i, status, wall_seconds() - start);
}

}  // namespace tissu
