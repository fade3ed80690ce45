// OpenMP regions that libraries open (CHOLMOD's factorization) run on the calling thread.
#pragma once

#include <cstdint>

namespace tissu {

// While one is alive on a thread, the OpenMP regions opened on that thread run their body
// there, once, as code outside any region runs it (omp_get_num_threads() is 1), without
// the team of one that libgomp otherwise sets up and ends with a system call per region.
class SerialOpenMpScope {
 public:
  SerialOpenMpScope();
  ~SerialOpenMpScope();
  SerialOpenMpScope(const SerialOpenMpScope&) = delete;
  SerialOpenMpScope& operator=(const SerialOpenMpScope&) = delete;

 private:
  int saved_levels_;
};

// Regions run that way since the process started (every thread).
int64_t serial_openmp_regions();

}  // namespace tissu
