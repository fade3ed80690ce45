// Clocks for measuring on a loaded machine, where wall time says little: processor time of
// the calling thread or of the whole process, and a monotonic wall clock; seconds.
#pragma once

#include <ctime>

namespace tissu {

inline double clock_seconds(clockid_t clock) {
  timespec t{};
  clock_gettime(clock, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

inline double thread_cpu_seconds() { return clock_seconds(CLOCK_THREAD_CPUTIME_ID); }
inline double process_cpu_seconds() { return clock_seconds(CLOCK_PROCESS_CPUTIME_ID); }  // every thread, also finished ones
inline double wall_seconds() { return clock_seconds(CLOCK_MONOTONIC); }

}  // namespace tissu
