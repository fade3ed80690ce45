// Work sharing for the simulation step: helper threads run independent items.
#pragma once

#include <functional>

namespace tissu {

// Runs body(i) for i in [0, count) on at most `threads` threads (the calling thread
// included; body must not throw); with threads <= 1 in order on the calling thread. The
// helper threads belong to the calling thread and live as long as it. Each thread takes a
// contiguous share of the items (with `cost`, of about equal total cost; else of equal
// count), the same share at every call, so the memory of its items stays in its core's
// cache. Items must not write the same memory, and results must not depend on which
// thread runs an item.
void parallel_for(int threads, int count, const std::function<void(int)>& body,
                  const double* cost = nullptr);

// parallel_for over [0, count) cut into consecutive ranges of `per_range` indices (the
// last one shorter): body(first, end) for each.
void parallel_for_ranges(int threads, int count, int per_range,
                         const std::function<void(int, int)>& body);

// Name of the helper threads parallel_for starts (for per-thread CPU accounting).
constexpr const char* kSimulationHelperThreadName = "tissu-sim";

// The number of processors this process may run on (at least 1).
int available_processors();

}  // namespace tissu
