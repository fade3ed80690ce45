// One job of a batch as a child `tissu run` or `tissu render` process, its stdout and
// stderr in DIR/jobs/<name>/log.txt, its end recorded in DIR/jobs/<name>/state.json.
#pragma once

#include <sys/types.h>

#include <string>

#include "app/batch_plan.h"

namespace tissu {

// The tissu program itself (/proc/self/exe), which the jobs run.
std::string tissu_program();

// Records job i as running and starts it; returns the child's process id.
// Throws OutputError when the log cannot be opened or the process cannot start.
pid_t start_job(const BatchPlan& plan, size_t i, const std::string& executor);

// Records how job i ended from its wait status: done (exit 0), interrupted (exit 130 or
// SIGINT/SIGTERM) or failed, with the last line of its log as the error. Returns the state.
JobState finish_job(const BatchPlan& plan, size_t i, int wait_status, double wall_s);

// start_job, wait, finish_job: for one task of a scheduler's job array.
JobState run_job_here(const BatchPlan& plan, size_t i, const std::string& executor);

}  // namespace tissu
