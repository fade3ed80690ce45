// Known answers for every integrator: free fall, energy behaviour, position correction.
#include <gtest/gtest.h>

#include "physics/diagnostics.h"
#include "physics/step.h"
#include "test_meshes.h"

namespace tissu {
namespace {

constexpr double kG = 9.81;  // m/s^2

struct FreeFallCase {
  Integrator integrator;
  double position_factor;  // y = -g h^2 * position_factor(n)
  double velocity_factor;  // v = -g t * velocity_factor
  bool explicit_positions;  // explicit Euler: n (n - 1) / 2 instead of n (n + 1) / 2
};

class FreeFall : public ::testing::TestWithParam<FreeFallCase> {};

// reference.md: from rest, after n steps of h: explicit Euler y = -g h^2 n (n - 1) / 2;
// symplectic and backward Euler y = -g h^2 n (n + 1) / 2; the paper's variant half of that.
TEST_P(FreeFall, MatchesExactDiscreteFormula) {
  const FreeFallCase& c = GetParam();
  Vec3List x;
  Model m = testing::grid_model(0.2, 0.1, 4, 3, 0.3, 1, &x);
  m.material = testing::test_material();
  m.gravity = Vec3(0, 0, -kG);
  m.integrator = c.integrator;
  m.dt = 1e-4;  // below the explicit stability limit of this sheet (~3e-4 s)
  precompute_rest(m);
  State s;
  s.x = x;
  s.v.assign(x.size(), Vec3::Zero());
  Workspace ws;
  const int n = 200;
  for (int k = 0; k < n; ++k) ASSERT_FALSE(step(m, s, ws).has_value());
  const double h = m.dt;
  const double steps = c.explicit_positions ? n * (n - 1) / 2.0 : n * (n + 1) / 2.0;
  const double z = -kG * h * h * steps * c.position_factor;
  const double vz = -kG * n * h * c.velocity_factor;
  for (size_t i = 0; i < x.size(); ++i) {
    EXPECT_NEAR(s.x[i].z(), z, 1e-9 * std::fabs(z)) << "vertex " << i;
    EXPECT_NEAR(s.x[i].x(), x[i].x(), 1e-12);
    EXPECT_NEAR(s.v[i].z(), vz, 1e-9 * std::fabs(vz));
  }
  EXPECT_DOUBLE_EQ(s.t, n * h);
}

INSTANTIATE_TEST_SUITE_P(
    Integrators, FreeFall,
    ::testing::Values(FreeFallCase{Integrator::ExplicitEuler, 1.0, 1.0, true},
                      FreeFallCase{Integrator::SymplecticEuler, 1.0, 1.0, false},
                      FreeFallCase{Integrator::BenameurDjedi, 0.5, 0.5, false},
                      FreeFallCase{Integrator::BackwardEuler, 1.0, 1.0, false}),
    [](const auto& info) { return std::string(integrator_name(info.param.integrator)); });

// Energy series of an undamped, pre-stretched free sheet released from rest.
std::vector<double> energy_series(Integrator integrator, int steps) {
  Vec3List x;
  Model m = testing::grid_model(0.2, 0.2, 8, 8, 0.3, 4, &x);
  m.material = testing::test_material();
  m.integrator = integrator;
  m.dt = 1e-4;
  precompute_rest(m);
  State s;
  s.x = x;
  for (Vec3& p : s.x) p = Vec3(1.05 * p.x(), 1.03 * p.y(), 0.002 * p.x() * p.y() / 0.01);
  s.v.assign(x.size(), Vec3::Zero());
  Workspace ws;
  std::vector<double> energy;
  for (int k = 0; k < steps; ++k) {
    if (step(m, s, ws)) break;
    energy.push_back(kinetic_energy(m, s.v) + elastic_energy(m, s.x));
  }
  return energy;
}

double mean(const std::vector<double>& e, size_t begin, size_t end) {
  double sum = 0.0;
  for (size_t i = begin; i < end; ++i) sum += e[i];
  return sum / static_cast<double>(end - begin);
}

// reference.md: undamped symplectic Euler oscillates around a shadow energy without drift.
TEST(Energy, UndampedSymplecticEulerDoesNotDrift) {
  const std::vector<double> e = energy_series(Integrator::SymplecticEuler, 20000);
  ASSERT_EQ(e.size(), 20000u);
  const size_t tenth = e.size() / 10;
  const double drift = mean(e, e.size() - tenth, e.size()) - mean(e, 0, tenth);
  const auto [lo, hi] = std::minmax_element(e.begin(), e.end());
  const double oscillation = *hi - *lo;
  EXPECT_GT(oscillation, 0.0);
  EXPECT_LT(std::fabs(drift), 0.1 * oscillation) << "drift " << drift;
  EXPECT_LT(*hi, 1.5 * e.front());
}

// The same run with explicit Euler gains energy: the test above can tell them apart.
TEST(Energy, UndampedExplicitEulerGainsEnergy) {
  const std::vector<double> e = energy_series(Integrator::ExplicitEuler, 20000);
  ASSERT_GT(e.size(), 10u);
  EXPECT_GT(e.back(), 1.5 * e.front());
}

// Section 3 as printed: v = 1 m/s, h = 0.1 s, threshold 0.03 m, 3 iterations: the step of
// 0.1 m is halved to 0.05, then 0.025; the last measured distance (0.025) is below the
// threshold, so the velocity is left as it was.
TEST(PositionCorrection, FollowsThePrintedAlgorithm) {
  Vec3List x;
  Model m = testing::grid_model(0.1, 0.1, 1, 1, 0.0, 1, &x);
  m.material = testing::test_material();
  m.integrator = Integrator::SymplecticEuler;
  m.dt = 0.1;
  m.position_correction = PositionCorrection{0.03, 3};
  precompute_rest(m);
  State s;
  s.x = x;
  s.v.assign(x.size(), Vec3(1.0, 0.0, 0.0));
  Workspace ws;
  ASSERT_FALSE(step(m, s, ws));
  for (size_t i = 0; i < x.size(); ++i) {
    EXPECT_NEAR(s.x[i].x() - x[i].x(), 0.025, 1e-10);
    EXPECT_NEAR(s.v[i].x(), 1.0, 1e-9);
  }
  // With 2 iterations the last distance measured is 0.05 > threshold: v = 0.05 / 0.1.
  m.position_correction = PositionCorrection{0.03, 2};
  s.x = x;
  s.v.assign(x.size(), Vec3(1.0, 0.0, 0.0));
  ASSERT_FALSE(step(m, s, ws));
  for (size_t i = 0; i < x.size(); ++i) {
    EXPECT_NEAR(s.x[i].x() - x[i].x(), 0.025, 1e-10);
    EXPECT_NEAR(s.v[i].x(), 0.25, 1e-9);
  }
}

TEST(Divergence, RunawayIsDetectedWithStepAndVertex) {
  Vec3List x;
  Model m = testing::grid_model(0.2, 0.2, 8, 8, 0.3, 4, &x);
  m.material = testing::test_material();
  m.integrator = Integrator::ExplicitEuler;
  m.dt = 5e-3;  // far above the explicit stability limit (~4e-4 s here)
  precompute_rest(m);
  State s;
  s.x = x;
  for (Vec3& p : s.x) p *= 1.05;
  s.v.assign(x.size(), Vec3::Zero());
  Workspace ws;
  std::optional<Divergence> d;
  for (int k = 0; k < 1000 && !d; ++k) d = step(m, s, ws);
  ASSERT_TRUE(d.has_value());
  EXPECT_GE(d->step, 1);
  EXPECT_GE(d->vertex, 0);
  EXPECT_LT(d->vertex, m.num_vertices());
  EXPECT_FALSE(d->reason.empty());
}

TEST(Pins, PinnedVerticesDoNotMove) {
  Vec3List x;
  Model m = testing::grid_model(0.2, 0.2, 4, 4, 0.2, 2, &x);
  m.material = testing::test_material();
  m.gravity = Vec3(0, 0, -kG);
  m.dt = 1e-4;
  m.pinned.assign(x.size(), 0);
  m.pinned[0] = m.pinned[4] = 1;
  precompute_rest(m);
  for (Integrator integrator : {Integrator::ExplicitEuler, Integrator::SymplecticEuler,
                                Integrator::BenameurDjedi, Integrator::BackwardEuler}) {
    m.integrator = integrator;
    State s;
    s.x = x;
    s.v.assign(x.size(), Vec3::Zero());
    Workspace ws;
    for (int k = 0; k < 200; ++k) ASSERT_FALSE(step(m, s, ws));
    EXPECT_EQ(s.x[0], x[0]) << integrator_name(integrator);
    EXPECT_EQ(s.x[4], x[4]);
    EXPECT_LT(s.x[12].z(), -1e-4) << "free vertices fall";
  }
}

}  // namespace
}  // namespace tissu
