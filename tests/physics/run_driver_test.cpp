// The run driver: samples by time on and between steps (checked against free fall by hand),
// samples by step, a run an observer stops, an interrupt, and a divergence that ends on the
// last good state.
#include <gtest/gtest.h>

#include <cmath>

#include "physics/run_driver.h"
#include "test_meshes.h"

namespace tissu {
namespace {

constexpr double kG = 9.81;  // m/s^2

// Records what the driver hands it: samples asked for by time (`times`, s) or every
// `every` steps, the states reached, and the state the run ended on.
class Recorder : public RunObserver {
 public:
  std::vector<double> times;  // s, ascending
  long long every = 0;
  long long max_samples = -1;  // wants no more after this many samples; -1 = all

  std::vector<SamplePoint> points;
  std::vector<State> states;
  std::vector<long long> reached_steps;
  int finished = 0;
  State end;
  RunEnd end_kind = RunEnd::Completed;

  std::optional<double> next_sample_time() const override {
    if (next_ == times.size()) return std::nullopt;
    return times[next_];
  }
  long long sample_every() const override { return every; }
  void sample(const State& state, const SamplePoint& point) override {
    if (every == 0) ++next_;  // a sample by time (the tests ask for one kind or the other)
    points.push_back(point);
    states.push_back(state);
  }
  void reached(const State&, long long steps) override { reached_steps.push_back(steps); }
  bool wants_more() const override {
    return max_samples < 0 || static_cast<long long>(points.size()) < max_samples;
  }
  void finish(const State& state, const DriveResult& result) override {
    ++finished;
    end = state;
    end_kind = result.end;
  }

 private:
  size_t next_ = 0;
};

// A free cotton sheet falling under gravity with symplectic Euler: a rigid motion, so after
// n steps of h every vertex is at z = -g h^2 n (n + 1) / 2 with v = -g h n.
testing::Sheet falling_sheet(double h) {
  return testing::cotton_sheet(0.3, 6, Integrator::SymplecticEuler, h);
}
double z_after(int n, double h) { return -kG * h * h * n * (n + 1) / 2.0; }

TEST(RunDriver, SamplesOnStepsAreExactAndBetweenStepsInterpolated) {
  const double h = 1e-3;  // s
  testing::Sheet sheet = falling_sheet(h);
  Recorder rec;
  rec.times = {0.0, 3 * h, 3.25 * h, 5 * h};
  DriveSpec spec;
  spec.steps = 6;
  const DriveResult result = drive(sheet.model, sheet.state, spec, {&rec});
  EXPECT_EQ(result.end, RunEnd::Completed);
  EXPECT_EQ(result.steps_done, 6);
  EXPECT_EQ(result.totals.steps, 6);
  EXPECT_EQ(sheet.state.step, 6);
  ASSERT_EQ(rec.points.size(), 4u);
  const bool interpolated[] = {false, false, true, false};
  const long long steps[] = {0, 3, 3, 5};
  for (size_t k = 0; k < 4; ++k) {
    EXPECT_EQ(rec.points[k].time, rec.times[k]);
    EXPECT_EQ(rec.points[k].interpolated, interpolated[k]) << k;
    EXPECT_EQ(rec.points[k].steps, steps[k]) << k;
  }
  // At 3.25 h, a quarter of the way from step 3 to step 4: by hand,
  // z = 0.75 z3 + 0.25 z4 = -g h^2 (0.75 * 6 + 0.25 * 10) = -7 g h^2, v = -3.25 g h.
  const State& between = rec.states[2];
  EXPECT_DOUBLE_EQ(between.t, 3.25 * h);
  EXPECT_NEAR(z_after(3, h), -6 * kG * h * h, 1e-18);
  for (size_t i = 0; i < between.x.size(); ++i) {
    EXPECT_NEAR(rec.states[0].x[i].z(), 0.0, 1e-15);
    EXPECT_NEAR(rec.states[1].x[i].z(), z_after(3, h), 1e-12);
    EXPECT_NEAR(between.x[i].z(), -7.0 * kG * h * h, 1e-12);
    EXPECT_NEAR(between.v[i].z(), -3.25 * kG * h, 1e-12);
    EXPECT_NEAR(rec.states[3].x[i].z(), z_after(5, h), 1e-12);
    EXPECT_NEAR(rec.states[3].v[i].z(), -5 * kG * h, 1e-12);
  }
  // Every state is reached once, the first included; the run ends once, on step 6.
  EXPECT_EQ(rec.reached_steps, (std::vector<long long>{0, 1, 2, 3, 4, 5, 6}));
  EXPECT_EQ(rec.finished, 1);
  EXPECT_EQ(rec.end.step, 6);
}

TEST(RunDriver, SamplesByStepAndStopsWhenAnObserverWantsNoMore) {
  testing::Sheet sheet = falling_sheet(1e-3);
  Recorder rec;
  rec.every = 2;
  rec.max_samples = 3;  // steps 0, 2 and 4
  DriveSpec spec;
  spec.steps = 100;
  const DriveResult result = drive(sheet.model, sheet.state, spec, {&rec});
  EXPECT_EQ(result.end, RunEnd::Stopped);
  EXPECT_EQ(result.steps_done, 4);
  ASSERT_EQ(rec.points.size(), 3u);
  for (size_t k = 0; k < 3; ++k) {
    EXPECT_EQ(rec.points[k].steps, 2 * static_cast<long long>(k));
    EXPECT_FALSE(rec.points[k].interpolated);
    EXPECT_EQ(rec.states[k].step, 2 * static_cast<long long>(k));
  }
  EXPECT_EQ(rec.finished, 1);
  EXPECT_EQ(rec.end_kind, RunEnd::Stopped);
  EXPECT_EQ(rec.end.step, 4);
}

TEST(RunDriver, AnInterruptEndsTheRunBeforeTheNextStep) {
  testing::Sheet sheet = falling_sheet(1e-3);
  Recorder rec;
  int polls = 0;
  DriveSpec spec;
  spec.steps = 100;
  spec.interrupted = [&polls] { return ++polls > 7; };
  const DriveResult result = drive(sheet.model, sheet.state, spec, {&rec});
  EXPECT_EQ(result.end, RunEnd::Interrupted);
  EXPECT_EQ(result.steps_done, 7);
  EXPECT_EQ(sheet.state.step, 7);
  EXPECT_EQ(rec.end_kind, RunEnd::Interrupted);
}

// A sheet stretched to 1.5 times its rest size, stepped by explicit Euler far above its
// stable step: it blows up within a few hundred steps.
testing::Sheet blowing_up_sheet() {
  testing::Sheet s = testing::cotton_sheet(0.3, 6, Integrator::ExplicitEuler, 2e-3);
  for (Vec3& x : s.state.x) x *= 1.5;
  return s;
}

TEST(RunDriver, ADivergenceEndsOnTheLastGoodStateWhenAsked) {
  testing::Sheet sheet = blowing_up_sheet();
  Recorder rec;
  DriveSpec spec;
  spec.steps = 100000;
  spec.end_on_last_good = true;
  const DriveResult result = drive(sheet.model, sheet.state, spec, {&rec});
  ASSERT_EQ(result.end, RunEnd::Diverged);
  ASSERT_TRUE(result.divergence);
  const long long good = result.steps_done - 1;  // the failed step is not kept
  EXPECT_EQ(sheet.state.step, good);
  EXPECT_EQ(rec.end_kind, RunEnd::Diverged);
  EXPECT_EQ(rec.end.step, good);
  EXPECT_EQ(rec.reached_steps.back(), good);

  // The same steps taken directly: the state shown is the one `good` steps in.
  testing::Sheet direct = blowing_up_sheet();
  Workspace ws;
  for (long long k = 0; k < good; ++k) ASSERT_FALSE(step(direct.model, direct.state, ws));
  EXPECT_EQ(sheet.state.x, direct.state.x);
  EXPECT_EQ(sheet.state.v, direct.state.v);
  EXPECT_EQ(sheet.state.t, direct.state.t);
  for (const Vec3& x : sheet.state.x) EXPECT_TRUE(x.allFinite());

  // Without end_on_last_good the run ends on the failed step.
  testing::Sheet kept = blowing_up_sheet();
  spec.end_on_last_good = false;
  const DriveResult failed = drive(kept.model, kept.state, spec, {});
  EXPECT_EQ(failed.end, RunEnd::Diverged);
  EXPECT_EQ(failed.steps_done, result.steps_done);
  EXPECT_EQ(kept.state.step, result.steps_done);
}

}  // namespace
}  // namespace tissu
