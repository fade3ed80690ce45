// The stability bisection on fake predicates with known thresholds.
#include <gtest/gtest.h>

#include "study/bisect.h"

namespace tissu {
namespace {

// Stable strictly below `threshold`; counts calls.
struct Threshold {
  double threshold;
  int calls = 0;
  bool operator()(double dt) {
    ++calls;
    return dt < threshold;
  }
};

class BisectThreshold : public ::testing::TestWithParam<std::pair<double, double>> {};

TEST_P(BisectThreshold, BracketsTheThresholdToThePrecision) {
  const auto [threshold, start] = GetParam();
  Threshold predicate{threshold};
  BisectionOptions o;
  o.start = start;
  o.min = 1e-7;
  o.max = 1.0 / 30.0;
  o.precision = 0.1;
  const BisectionResult r =
      bisect_largest_stable([&](double dt) { return predicate(dt); }, o);
  EXPECT_FALSE(r.stable_at_max);
  EXPECT_FALSE(r.unstable_at_min);
  EXPECT_LT(r.largest_stable, threshold);
  EXPECT_GE(r.smallest_unstable, threshold);
  EXPECT_LE(r.smallest_unstable / r.largest_stable, 1.1 + 1e-12);
  // Every trial agrees with the predicate, and the count is logarithmic.
  for (const BisectionTrial& t : r.trials) EXPECT_EQ(t.stable, t.dt < threshold) << t.dt;
  EXPECT_EQ(static_cast<int>(r.trials.size()), predicate.calls);
  EXPECT_LE(predicate.calls, 25);
}

INSTANTIATE_TEST_SUITE_P(
    Thresholds, BisectThreshold,
    ::testing::Values(std::make_pair(1.23e-4, 1.0 / 30.0),  // search down from the top
                      std::make_pair(1.23e-4, 1e-6),        // search up from below
                      std::make_pair(0.02, 1e-4), std::make_pair(3.3e-7, 1.0 / 30.0),
                      std::make_pair(1e-4, 1e-4)));         // start exactly on it

TEST(Bisect, StableEverywhereReportsAtLeastTheMaximum) {
  BisectionOptions o;
  o.start = 1e-3;
  o.max = 0.05;
  const BisectionResult r = bisect_largest_stable([](double) { return true; }, o);
  EXPECT_TRUE(r.stable_at_max);
  EXPECT_DOUBLE_EQ(r.largest_stable, 0.05);
  EXPECT_EQ(r.smallest_unstable, 0.0);
}

TEST(Bisect, UnstableEverywhereReportsBelowTheMinimum) {
  BisectionOptions o;
  o.start = 1e-3;
  o.min = 1e-6;
  const BisectionResult r = bisect_largest_stable([](double) { return false; }, o);
  EXPECT_TRUE(r.unstable_at_min);
  EXPECT_EQ(r.largest_stable, 0.0);
  EXPECT_DOUBLE_EQ(r.smallest_unstable, 1e-6);
}

TEST(Bisect, FinerPrecisionNarrowsTheBracket) {
  BisectionOptions o;
  o.start = 1e-2;
  o.precision = 0.01;
  const BisectionResult r = bisect_largest_stable([](double dt) { return dt <= 7.77e-4; }, o);
  EXPECT_LE(r.largest_stable, 7.77e-4);
  EXPECT_GT(r.smallest_unstable, 7.77e-4);
  EXPECT_LE(r.smallest_unstable / r.largest_stable, 1.01 + 1e-12);
}

TEST(Bisect, BadOptionsThrow) {
  BisectionOptions o;
  o.min = 0.0;
  EXPECT_THROW(bisect_largest_stable([](double) { return true; }, o), std::invalid_argument);
}

}  // namespace
}  // namespace tissu
