// CPU clocks for measuring the renderer on a loaded machine, where wall time says little:
// the calling thread, the whole process, and threads picked by name (llvmpipe names its
// rasterizer threads "llvmpipe-N").
#pragma once

#include <string>

namespace tissu {

double thread_cpu_seconds();   // CLOCK_THREAD_CPUTIME_ID of the calling thread
double process_cpu_seconds();  // CLOCK_PROCESS_CPUTIME_ID: every thread, also finished ones
double wall_seconds();         // CLOCK_MONOTONIC

// CPU time so far of the live threads of this process whose name starts with `prefix`
// (from /proc/self/task/*/schedstat; 0 where /proc is not available).
double named_threads_cpu_seconds(const std::string& prefix);

}  // namespace tissu
