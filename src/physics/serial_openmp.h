// OpenMP regions that libraries open (CHOLMOD's factorization) run on the calling thread.
#pragma once

#include <cstdint>

namespace tissu {

// While one is alive on a thread outside any OpenMP region, the regions opened on that
// thread run their body there, once, as code outside any region runs it
// (omp_get_num_threads() is 1), without the team of one that libgomp otherwise sets up and
// ends with a system call per region. Inside another region's team they get a team of
// one from the runtime. (Where the runtime's own entry point cannot be found, a static
// link, every region runs that way.)
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
