// Error and energy measures on constructed inputs with known answers.
#include <gtest/gtest.h>

#include <cmath>

#include "collision/closed_surface.h"
#include "collision/test_surfaces.h"
#include "study/metrics.h"

namespace tissu {
namespace {

TEST(PositionError, IdenticalConfigurationsHaveZeroError) {
  const Vec3List a = {Vec3(0, 0, 0), Vec3(1, 2, 3), Vec3(-1, 0.5, 2)};
  const PositionError e = position_error(a, a);
  EXPECT_EQ(e.rms, 0.0);
  EXPECT_EQ(e.max, 0.0);
}

TEST(PositionError, RmsAndMaxOfKnownDisplacements) {
  // Displacements of length 3, 4 and 0 (a 3-4-5 pair along different axes).
  const Vec3List a = {Vec3(0, 0, 0), Vec3(1, 1, 1), Vec3(5, 5, 5)};
  const Vec3List b = {Vec3(3, 0, 0), Vec3(1, 1, -3), Vec3(5, 5, 5)};
  const PositionError e = position_error(a, b);
  EXPECT_NEAR(e.rms, std::sqrt((9.0 + 16.0 + 0.0) / 3.0), 1e-15);
  EXPECT_DOUBLE_EQ(e.max, 4.0);
  EXPECT_EQ(e.max_vertex, 1);
  // Symmetric in its arguments.
  const PositionError r = position_error(b, a);
  EXPECT_DOUBLE_EQ(r.rms, e.rms);
  EXPECT_DOUBLE_EQ(r.max, e.max);
}

TEST(PositionError, UniformTranslationGivesItsLengthForBoth) {
  Vec3List a, b;
  const Vec3 shift(0.001, -0.002, 0.002);  // 3 mm
  for (int i = 0; i < 100; ++i) {
    a.emplace_back(0.01 * i, std::sin(i), std::cos(i));
    b.push_back(a.back() + shift);
  }
  const PositionError e = position_error(a, b);
  EXPECT_NEAR(e.rms, 0.003, 1e-15);
  EXPECT_NEAR(e.max, 0.003, 1e-15);
}

TEST(PositionError, EmptyInputIsZero) {
  const PositionError e = position_error({}, {});
  EXPECT_EQ(e.rms, 0.0);
  EXPECT_EQ(e.max_vertex, -1);
}

// One free triangle of 1 m^2 rest area: mass, potential and kinetic energy by hand.
Model one_triangle(Vec3List& x) {
  Model m;
  m.rest_uv = {Vec2(0, 0), Vec2(2, 0), Vec2(0, 1)};  // area 1 m^2
  m.triangles = {Tri(0, 1, 2)};
  m.pinned.assign(3, 0);
  m.material.density = 0.3;  // kg/m^2: 0.1 kg per vertex
  m.material.weft = m.material.warp = 100.0;
  m.material.shear = 10.0;
  precompute_rest(m);
  x = {Vec3(0, 0, 1), Vec3(2, 0, 1), Vec3(0, 1, 1)};
  return m;
}

TEST(Energy, KineticPotentialAndElasticOfARigidState) {
  Vec3List x;
  Model m = one_triangle(x);
  m.gravity = Vec3(0, 0, -10);
  const Vec3List v = {Vec3(1, 0, 0), Vec3(1, 0, 0), Vec3(1, 0, 0)};
  const Energy e = measure_energy(m, x, v);
  EXPECT_NEAR(total_mass(m), 0.3, 1e-15);
  EXPECT_NEAR(e.kinetic, 0.5 * 0.3 * 1.0, 1e-14);
  EXPECT_NEAR(e.potential, 0.3 * 10 * 1.0, 1e-14);  // -sum m g.x, all at z = 1 m
  EXPECT_NEAR(e.elastic, 0.0, 1e-14);                 // rest shape
  EXPECT_NEAR(e.total(), 0.15 + 3.0, 1e-13);
}

TEST(CentreOfMass, EqualMassesGiveTheMeanPosition) {
  Vec3List x;
  const Model m = one_triangle(x);
  const Vec3 c = centre_of_mass(m, x);
  EXPECT_NEAR(c.x(), 2.0 / 3.0, 1e-15);
  EXPECT_NEAR(c.y(), 1.0 / 3.0, 1e-15);
  EXPECT_NEAR(c.z(), 1.0, 1e-15);
}

TEST(MaxSpeed, LargestVertexSpeedOrZero) {
  EXPECT_EQ(max_speed({Vec3(3, 4, 0), Vec3(0, 0, -1)}), 5.0);
  EXPECT_EQ(max_speed({}), 0.0);
}

TEST(EnergyScale, GravityWorkOverTheClothSizePlusDrivers) {
  Vec3List x;
  Model m = one_triangle(x);
  State s;
  s.x = x;
  s.v.assign(3, Vec3::Zero());
  // Nothing can do work: the floor of 1e-9 J.
  EXPECT_DOUBLE_EQ(energy_scale(m, s), 1e-9);
  // Gravity: M |g| L with L = the bounding-box diagonal, sqrt(2^2 + 1^2) m.
  m.gravity = Vec3(0, 0, -10);
  EXPECT_NEAR(energy_scale(m, s), 0.3 * 10 * std::sqrt(5.0), 1e-12);
  // A moving sphere adds M (2 v)^2 / 2 for its largest speed v = 3 + 0.1 * 2 pi / 0.5 m/s.
  Obstacle ob;
  ob.radius = 0.1;
  ob.center = Vec3(5, 5, 5);
  ob.motion.velocity = Vec3(3, 0, 0);
  ob.motion.amplitude = Vec3(0, 0.1, 0);
  ob.motion.period = 0.5;
  m.obstacles.push_back(ob);
  const double v = 3.0 + 0.1 * 2 * M_PI / 0.5;
  EXPECT_NEAR(max_obstacle_speed(ob), v, 1e-12);
  EXPECT_NEAR(energy_scale(m, s), 0.3 * 10 * std::sqrt(5.0) + 0.5 * 0.3 * 4 * v * v, 1e-12);
}

// Keyframed motion supplies energy too: a sphere lifted 0.1 m in 1 s once counted as still,
// and a run that it lifted was reported as diverged. A segment moves at its translation over
// its duration, and a mesh's turn moves its farthest point at the angle over the duration
// times that distance.
TEST(EnergyScale, KeyframedObstacleMovesAtItsFastestSegment) {
  Obstacle ball;
  ball.radius = 0.1;
  Keyframe rest, lifted, held;
  lifted.time = 1.0;
  lifted.translation = Vec3(0, 0, 0.1);
  held.time = 1.5;
  held.translation = Vec3(0, 0, 0.1);
  ball.motion.keyframes = {rest, lifted, held};
  EXPECT_NEAR(max_obstacle_speed(ball), 0.1, 1e-12);
  Obstacle drifting = ball;
  drifting.motion.keyframes.clear();
  drifting.motion.velocity = Vec3(0, 0, 0.1);
  EXPECT_NEAR(max_obstacle_speed(drifting), max_obstacle_speed(ball), 1e-12);

  // A unit cube turned a quarter turn about z in 0.5 s: its corners, sqrt(3)/2 m from the
  // centre, move at (pi/2) (sqrt(3)/2) / 0.5 m/s.
  const testing::SurfaceData cube = testing::box_surface(Vec3(-0.5, -0.5, -0.5), Vec3(0.5, 0.5, 0.5));
  Obstacle box;
  box.kind = ObstacleKind::Mesh;
  box.surface = std::make_shared<const ClosedSurface>(cube.vertices, cube.triangles, "cube");
  Keyframe start, turned;
  turned.time = 0.5;
  turned.rotation = Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 2, Vec3::UnitZ()));
  box.motion.keyframes = {start, turned};
  EXPECT_NEAR(max_obstacle_speed(box), (M_PI / 2) * (std::sqrt(3.0) / 2) / 0.5, 1e-12);
}

}  // namespace
}  // namespace tissu
