#include "app/batch_local.h"

#include <sys/wait.h>

#include <cerrno>
#include <csignal>
#include <map>

#include "app/batch_job.h"
#include "app/signals.h"
#include "core/cpu_clock.h"
#include "core/error.h"
#include "core/partial_file.h"
#include "video/progress_bar.h"

namespace tissu {

bool run_local_pool(const BatchPlan& plan, const std::vector<size_t>& todo,
                    const LocalPoolOptions& options) {
  struct Running {
    size_t job;
    double start;
  };
  std::map<pid_t, Running> running;
  install_interrupt_handlers();
  ProgressBar progress = ProgressBar::on_stderr("batch", static_cast<long long>(todo.size()));
  size_t next = 0, finished = 0;
  bool forwarded = false;
  while (next < todo.size() || !running.empty()) {
    while (!interrupt_requested() && next < todo.size() &&
           static_cast<int>(running.size()) < options.processes) {
      const size_t job = todo[next++];
      running[start_job(plan, job, "local")] = {job, wall_seconds()};
    }
    if (interrupt_requested() && !forwarded) {
      for (const auto& [pid, r] : running) ::kill(pid, SIGINT);
      forwarded = true;
    }
    if (running.empty()) break;
    int status = 0;
    const pid_t pid = waitpid(-1, &status, 0);
    if (pid < 0) {
      if (errno == EINTR) continue;  // a signal: forward it above
      throw OutputError(std::string("batch: cannot wait for the jobs: ") + errno_text(errno));
    }
    const auto it = running.find(pid);
    if (it == running.end()) continue;
    finish_job(plan, it->second.job, status, wall_seconds() - it->second.start);
    running.erase(it);
    ++finished;
    if (options.progress) progress.update(static_cast<long long>(finished));
  }
  if (options.progress) progress.finish();
  return interrupt_requested();
}

}  // namespace tissu
