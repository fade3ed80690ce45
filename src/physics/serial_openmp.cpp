// CHOLMOD's supernodal factorization opens an OpenMP region per supernode: about 5,700 per
// factorization of the demo's matrix. With no active level libgomp still makes each a team
// of one and ends it with a futex wake, a system call of about 0.4 us in the virtual
// machines Tissu is measured on: a quarter of the factorization's time. libgomp has no
// switch for that, so the executable defines GOMP_parallel, the entry point GCC's code
// calls for every region (CHOLMOD imports no other). The dynamic linker binds every
// shared library's calls to the executable's definition first; it runs the body directly
// inside a SerialOpenMpScope and hands every other region to libgomp's.
#include "physics/serial_openmp.h"

#include <dlfcn.h>
#include <omp.h>

#include <atomic>

namespace tissu {
namespace {

thread_local int serial_scopes = 0;
std::atomic<int64_t> serial_regions{0};

using ParallelEntry = void (*)(void (*)(void*), void*, unsigned, unsigned);

// The OpenMP runtime's own GOMP_parallel (the version GCC 4.9 and later call); null only
// where no later object defines it (a static link).
ParallelEntry libgomp_parallel() {
  static const ParallelEntry entry = [] {
    void* found = dlvsym(RTLD_NEXT, "GOMP_parallel", "GOMP_4.0");
    if (found == nullptr) found = dlsym(RTLD_NEXT, "GOMP_parallel");
    return reinterpret_cast<ParallelEntry>(found);
  }();
  return entry;
}

}  // namespace

SerialOpenMpScope::SerialOpenMpScope() : saved_levels_(omp_get_max_active_levels()) {
  // No active level either, so that a region that reaches libgomp all the same (a program
  // that does not export GOMP_parallel) still runs on this thread.
  omp_set_max_active_levels(0);
  ++serial_scopes;
}

SerialOpenMpScope::~SerialOpenMpScope() {
  --serial_scopes;
  omp_set_max_active_levels(saved_levels_);
}

int64_t serial_openmp_regions() { return serial_regions.load(std::memory_order_relaxed); }

}  // namespace tissu

// A region run on one thread without a team is what OpenMP allows for any region (its
// thread count is an upper bound): outside any team, libgomp treats the body's
// worksharing loops, barriers and single constructs as the lone thread's. Inside another
// region's team the body would see that team (its thread count and number), so such a
// region goes to the runtime, which gives it a team of one under the scope's level limit.
extern "C" void GOMP_parallel(void (*body)(void*), void* data, unsigned num_threads,
                              unsigned flags) {
  const tissu::ParallelEntry next = tissu::libgomp_parallel();
  if ((tissu::serial_scopes > 0 && omp_get_level() == 0) || next == nullptr) {
    tissu::serial_regions.fetch_add(1, std::memory_order_relaxed);
    body(data);
    return;
  }
  next(body, data, num_threads, flags);
}
