// OpenMP regions inside a SerialOpenMpScope run once on the calling thread; outside one
// they get libgomp's threads (physics/serial_openmp.cpp). Built with -fopenmp, so the
// regions below are GCC's calls to GOMP_parallel, as CHOLMOD's are.
#include <omp.h>

#include <gtest/gtest.h>

#include <atomic>
#include <thread>
#include <vector>

#include "physics/serial_openmp.h"

namespace tissu {
namespace {

int threads_of_a_region() {
  int threads = 0;
#pragma omp parallel num_threads(2)
  {
#pragma omp single
    threads = omp_get_num_threads();
  }
  return threads;
}

TEST(SerialOpenMp, RegionsOutsideAScopeGetTheirThreads) {
  const int64_t before = serial_openmp_regions();
  EXPECT_EQ(threads_of_a_region(), 2);
  EXPECT_EQ(serial_openmp_regions(), before);
}

TEST(SerialOpenMp, RegionsInsideAScopeRunOnceOnTheCallingThread) {
  const std::thread::id caller = std::this_thread::get_id();
  std::atomic<int> bodies{0}, elsewhere{0};
  std::vector<int> visits(1000, 0);
  const int64_t before = serial_openmp_regions();
  {
    const SerialOpenMpScope scope;
#pragma omp parallel num_threads(4)
    {
      bodies += 1;
      if (std::this_thread::get_id() != caller || omp_get_num_threads() != 1) elsewhere += 1;
#pragma omp for schedule(dynamic, 7)
      for (int k = 0; k < 1000; ++k) visits[k] += 1;
#pragma omp barrier
    }
#pragma omp parallel for num_threads(4) schedule(static)
    for (int k = 0; k < 1000; ++k) visits[k] += 1;
  }
  EXPECT_EQ(bodies.load(), 1);
  EXPECT_EQ(elsewhere.load(), 0);
  for (int k = 0; k < 1000; ++k) ASSERT_EQ(visits[k], 2) << "iteration " << k;
  EXPECT_EQ(serial_openmp_regions(), before + 2);
  EXPECT_EQ(threads_of_a_region(), 2) << "threads again once the scope ends";
}

TEST(SerialOpenMp, ScopesNestAndAreOneThreads) {
  const SerialOpenMpScope outer;
  {
    const SerialOpenMpScope inner;
  }
  EXPECT_EQ(threads_of_a_region(), 1) << "the outer scope still holds";
  int other = 0;
  std::thread([&] { other = threads_of_a_region(); }).join();
  EXPECT_EQ(other, 2) << "another thread's regions are its own";
}

// A scope opened inside another region's team: its regions must not see that team (they
// would split their loops with threads that never run them), so each runs whole on a team
// of one.
TEST(SerialOpenMp, ScopeInsideATeamLeavesRegionsToTheRuntime) {
  std::vector<int> visits(2 * 1000, 0);
  std::atomic<int> wrong_team{0};
  const int64_t before = serial_openmp_regions();
#pragma omp parallel num_threads(2)
  {
    const int part = omp_get_thread_num();
    const SerialOpenMpScope scope;
#pragma omp parallel num_threads(4)
    {
      if (omp_get_num_threads() != 1) wrong_team += 1;
#pragma omp for schedule(static)
      for (int k = 0; k < 1000; ++k) visits[part * 1000 + k] += 1;
    }
  }
  EXPECT_EQ(wrong_team.load(), 0);
  for (int k = 0; k < 2000; ++k) ASSERT_EQ(visits[k], 1) << "iteration " << k;
  EXPECT_EQ(serial_openmp_regions(), before) << "no inner region ran without a team";
}

}  // namespace
}  // namespace tissu
