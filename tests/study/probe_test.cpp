// Measured runs: samples on and between steps, divergence, energy growth and obstacle
// penetration are always reported, never silent.
#include <gtest/gtest.h>

#include <cmath>

#include "study/probe.h"

namespace tissu {
namespace {

constexpr double kG = 9.81;  // m/s^2

// A small free silk sheet (about 50 triangles, edges about 4 cm) in the x-y plane at z = 0,
// falling. Its explicit stability limit is about 2.7e-4 s (edge / membrane wave speed).
Simulation sheet(const std::string& extra_json = "{}") {
  Json doc = Json::parse(R"({
    "name": "sheet", "dt": 1e-4, "steps": 10, "integrator": "symplectic_euler",
    "cloth": {"mesh": {"generate": "rectangle", "size": [0.2, 0.2], "triangles": 50,
                       "irregular": false},
              "material": "silk"},
    "gravity": [0, 0, -9.81]
  })");
  doc.merge_patch(Json::parse(extra_json));
  return build_simulation(parse_scene(doc, ""));
}

TEST(Probe, SamplesOnTheStepGridAreExactAndBetweenStepsInterpolated) {
  const Simulation base = sheet();
  const double h = 1e-4;
  ProbeSpec spec;
  spec.integrator = Integrator::SymplecticEuler;
  spec.dt = h;
  spec.duration = 20 * h;
  spec.sample_times = {10.5 * h, 10 * h, 20 * h};  // unsorted on purpose
  const ProbeResult r = run_probe(base, spec);
  ASSERT_EQ(r.status, ProbeStatus::Ok);
  EXPECT_EQ(r.steps, 20);
  EXPECT_EQ(r.steps_done, 20);
  EXPECT_NEAR(r.simulated_time, 20 * h, 1e-15);
  EXPECT_GT(r.wall_seconds, 0.0);
  ASSERT_EQ(r.samples.size(), 3u);
  // Free fall of a rigid sheet: z = -g h^2 n (n + 1) / 2 (reference.md).
  auto z_at = [h](int n) { return -kG * h * h * n * (n + 1) / 2.0; };
  EXPECT_DOUBLE_EQ(r.samples[0].time, 10 * h);
  EXPECT_FALSE(r.samples[0].interpolated);
  EXPECT_DOUBLE_EQ(r.samples[1].time, 10.5 * h);
  EXPECT_TRUE(r.samples[1].interpolated);
  EXPECT_FALSE(r.samples[2].interpolated);
  for (size_t i = 0; i < base.state.x.size(); ++i) {
    EXPECT_NEAR(r.samples[0].x[i].z(), z_at(10), 1e-14);
    EXPECT_NEAR(r.samples[1].x[i].z(), 0.5 * (z_at(10) + z_at(11)), 1e-14);
    EXPECT_NEAR(r.samples[2].x[i].z(), z_at(20), 1e-14);
    EXPECT_NEAR(r.samples[2].x[i].x(), base.state.x[i].x(), 1e-12);
  }
  // Energy of the samples: kinetic of v = -g t at the exact sample.
  const double mass = total_mass(base.model);
  EXPECT_NEAR(r.samples[2].energy.kinetic, 0.5 * mass * std::pow(kG * 20 * h, 2), 1e-15);
}

TEST(Probe, DurationNotOnTheGridRunsOneMoreStep) {
  ProbeSpec spec;
  spec.dt = 3e-4;
  spec.duration = 1e-3;
  const ProbeResult r = run_probe(sheet(), spec);
  EXPECT_EQ(r.steps, 4);
  EXPECT_EQ(r.steps_done, 4);
}

TEST(Probe, ExplicitEulerGainsEnergyAndIsFlagged) {
  // Explicit Euler in free fall gains m g^2 h^2 / 2 of total energy per step
  // (z = -g h^2 n (n - 1) / 2, v = -g n h); symplectic Euler loses as much.
  const Simulation base = sheet();
  ProbeSpec spec;
  spec.dt = 1e-4;
  spec.duration = 2e-3;
  spec.monitor_every = 1;
  spec.energy_margin = 1e-7;  // bound: start + 1e-7 * M g L, below one step's gain
  spec.integrator = Integrator::ExplicitEuler;
  const ProbeResult bad = run_probe(base, spec);
  EXPECT_EQ(bad.status, ProbeStatus::EnergyUnbounded);
  ASSERT_TRUE(bad.failure.has_value());
  EXPECT_GE(bad.failure->step, 1);
  EXPECT_GE(bad.failure->vertex, 0);
  EXPECT_NE(bad.failure->reason.find("exceeds the bound"), std::string::npos);
  EXPECT_FALSE(bad.stable());
  spec.integrator = Integrator::SymplecticEuler;
  const ProbeResult good = run_probe(base, spec);
  EXPECT_EQ(good.status, ProbeStatus::Ok) << (good.failure ? good.failure->reason : "");
}

// The sheet pre-stretched 20 % and explicit Euler far beyond its stability limit.
Simulation stretched_sheet() { return sheet(R"({"cloth": {"transform": {"scale": 1.2}}})"); }
ProbeSpec beyond_explicit_limit() {
  ProbeSpec spec;
  spec.integrator = Integrator::ExplicitEuler;
  spec.dt = 5e-3;
  return spec;
}

TEST(Probe, DivergenceIsReportedWithStepAndVertex) {
  ProbeSpec spec = beyond_explicit_limit();
  spec.duration = 1.0;
  const ProbeResult r = run_probe(stretched_sheet(), spec);
  ASSERT_NE(r.status, ProbeStatus::Ok);
  ASSERT_TRUE(r.failure.has_value());
  EXPECT_GE(r.failure->step, 1);
  EXPECT_GE(r.failure->vertex, 0);
  EXPECT_LT(r.steps_done, r.steps);
}

TEST(Probe, VertexInsideAnObstacleIsFlagged) {
  // A pinned vertex is never pushed out by collisions: put a sphere around it (after the
  // scene is built, since a scene's cloth must start outside its obstacles).
  Simulation base = sheet(R"({
    "cloth": {"pins": [{"vertices": [0]}]},
    "obstacles": [{"sphere": {"center": [-0.1, -0.1, 1.0], "radius": 0.01}}]
  })");
  base.model.obstacles[0].center = Vec3(-0.1, -0.1, 0.0);
  ProbeSpec spec;
  spec.dt = 1e-4;
  spec.duration = 5e-4;
  const ProbeResult r = run_probe(base, spec);
  EXPECT_EQ(r.status, ProbeStatus::Penetration);
  ASSERT_TRUE(r.failure.has_value());
  EXPECT_EQ(r.failure->vertex, 0);
  ASSERT_TRUE(r.min_clearance.has_value());
  EXPECT_LT(*r.min_clearance, -0.009);
}

// The paper's runs: a count of steps, no monitoring, the last good state kept and every
// state seen by an observer.
TEST(Probe, CountedRunEndsOnTheLastGoodStateAfterADivergence) {
  ProbeSpec spec = beyond_explicit_limit();
  spec.steps = 200;
  spec.monitored = false;
  spec.keep_end = true;
  std::vector<long long> seen;
  spec.observe = [&](const State& s) { seen.push_back(s.step); };
  const ProbeResult r = run_probe(stretched_sheet(), spec);
  ASSERT_EQ(r.status, ProbeStatus::Diverged);
  ASSERT_TRUE(r.failure.has_value());
  EXPECT_EQ(r.steps, 200);
  EXPECT_EQ(r.end.step, r.failure->step - 1);
  for (const Vec3& x : r.end.x) EXPECT_TRUE(x.allFinite());
  ASSERT_EQ(static_cast<long long>(seen.size()), r.failure->step);
  for (size_t i = 0; i < seen.size(); ++i) EXPECT_EQ(seen[i], static_cast<long long>(i));
}

TEST(Probe, CountedRunTakesExactlyItsSteps) {
  ProbeSpec spec;
  spec.dt = 1e-4;
  spec.duration = 1.0;  // ignored
  spec.steps = 7;
  spec.keep_end = true;
  const ProbeResult r = run_probe(sheet(), spec);
  EXPECT_EQ(r.status, ProbeStatus::Ok);
  EXPECT_EQ(r.steps_done, 7);
  EXPECT_EQ(r.end.step, 7);
}

TEST(Probe, InterruptStopsTheRun) {
  ProbeSpec spec;
  spec.dt = 1e-4;
  spec.duration = 1.0;
  int polls = 0;
  spec.interrupted = [&] { return ++polls > 5; };
  const ProbeResult r = run_probe(sheet(), spec);
  EXPECT_EQ(r.status, ProbeStatus::Interrupted);
  EXPECT_EQ(r.steps_done, 5);
}

TEST(Integrators, NamesRoundTripAndUnknownNamesAreBadInput) {
  for (Integrator i : all_integrators()) EXPECT_EQ(parse_integrator_name(integrator_name(i)), i);
  EXPECT_THROW(parse_integrator_name("rk4"), InputError);
}

}  // namespace
}  // namespace tissu
