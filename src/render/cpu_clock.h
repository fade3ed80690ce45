// Processor time of threads picked by name, for measuring the renderer (llvmpipe names its
// rasterizer threads "llvmpipe-N"); the other clocks are in core/cpu_clock.h.
#pragma once

#include <string>

#include "core/cpu_clock.h"

namespace tissu {

// CPU time so far of the live threads of this process whose name starts with `prefix`
// (from /proc/self/task/*/schedstat; 0 where /proc is not available).
double named_threads_cpu_seconds(const std::string& prefix);

}  // namespace tissu
