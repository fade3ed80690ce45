// Obstacles: exact signed distances, no vertex inside after any step, stable resting
// contact, friction.
#include <gtest/gtest.h>

#include "physics/diagnostics.h"
#include "physics/step.h"
#include "test_meshes.h"

namespace tissu {
namespace {

constexpr double kInsideTolerance = 1e-12;  // m: projection round-off

Obstacle sphere(Vec3 c, double r) {
  Obstacle o;
  o.kind = ObstacleKind::Sphere;
  o.center = c;
  o.radius = r;
  return o;
}

Obstacle cylinder(Vec3 c, Vec3 axis, double r, double length) {
  Obstacle o;
  o.kind = ObstacleKind::Cylinder;
  o.center = c;
  o.axis = axis.normalized();
  o.radius = r;
  o.half_length = length / 2;
  return o;
}

Obstacle plane(Vec3 p, Vec3 n) {
  Obstacle o;
  o.kind = ObstacleKind::Plane;
  o.center = p;
  o.axis = n.normalized();
  return o;
}

TEST(ObstacleDistance, KnownValues) {
  Vec3 n;
  const Obstacle s = sphere(Vec3(1, 0, 0), 0.5);
  EXPECT_DOUBLE_EQ(s.signed_distance(Vec3(1, 0, 2), 0, &n), 1.5);
  EXPECT_EQ(n, Vec3(0, 0, 1));
  EXPECT_DOUBLE_EQ(s.signed_distance(Vec3(1.2, 0, 0), 0, &n), -0.3);

  const Obstacle c = cylinder(Vec3::Zero(), Vec3(0, 1, 0), 0.5, 2.0);  // y in [-1, 1]
  EXPECT_DOUBLE_EQ(c.signed_distance(Vec3(0.8, 0.3, 0), 0, &n), 0.3);  // side
  EXPECT_TRUE(n.isApprox(Vec3(1, 0, 0)));
  EXPECT_DOUBLE_EQ(c.signed_distance(Vec3(0.1, 1.4, 0), 0, &n), 0.4);  // cap
  EXPECT_TRUE(n.isApprox(Vec3(0, 1, 0)));
  EXPECT_NEAR(c.signed_distance(Vec3(0.8, 1.4, 0), 0, &n), 0.5, 1e-15);  // rim: (0.3, 0.4)
  EXPECT_TRUE(n.isApprox(Vec3(0.6, 0.8, 0)));
  EXPECT_DOUBLE_EQ(c.signed_distance(Vec3(0.4, 0.0, 0), 0, &n), -0.1);  // inside, near side
  EXPECT_NEAR(c.signed_distance(Vec3(0.0, -0.95, 0), 0, &n), -0.05, 1e-15);  // inside, near cap
  EXPECT_TRUE(n.isApprox(Vec3(0, -1, 0)));

  const Obstacle p = plane(Vec3(0, 0, -1), Vec3(0, 0, 2));
  EXPECT_DOUBLE_EQ(p.signed_distance(Vec3(5, 3, -1.5), 0, &n), -0.5);
}

TEST(ObstacleDistance, MovingObstacle) {
  Obstacle s = sphere(Vec3::Zero(), 0.1);
  s.motion.velocity = Vec3(1, 0, 0);
  s.motion.amplitude = Vec3(0, 0, 0.2);
  s.motion.period = 2.0;
  Vec3 n;
  // t = 0.5: centre at (0.5, 0, 0.2 sin(pi/2)) = (0.5, 0, 0.2).
  EXPECT_NEAR(s.signed_distance(Vec3(0.5, 0, 0.5), 0.5, &n), 0.2, 1e-12);
  EXPECT_TRUE(s.velocity(0.5).isApprox(Vec3(1, 0, 0), 1e-12));
  EXPECT_TRUE(s.velocity(0.0).isApprox(Vec3(1, 0, 0.2 * M_PI), 1e-12));
}

// A sheet dropped onto an obstacle: after every step no vertex is inside.
struct DropResult {
  double worst_clearance = INFINITY;  // m, over all steps
  double final_max_speed = 0.0;       // m/s
  double final_kinetic = 0.0;         // J
  Vec3List x;
};

DropResult drop_on(const Obstacle& ob, double seconds, double friction, double height) {
  Vec3List x;
  Model m = testing::grid_model(0.6, 0.6, 16, 16, 0.3, 5, &x);
  m.material = testing::test_material();
  m.material.damping = 1e-5;  // s; explicit stability needs dt well below 1/(omega^2 tau)
  m.gravity = Vec3(0, 0, -9.81);
  m.air_damping = 0.5;
  m.integrator = Integrator::SymplecticEuler;
  m.dt = 1e-4;  // at 2e-4 s the smallest triangles of this mesh are beyond the stability limit
  m.obstacles = {ob};
  m.obstacles[0].friction = friction;
  precompute_rest(m);
  State s;
  s.x = x;
  for (Vec3& p : s.x) p.z() = height;
  s.v.assign(x.size(), Vec3::Zero());
  Workspace ws;
  DropResult r;
  const int steps = static_cast<int>(seconds / m.dt);
  for (int k = 0; k < steps; ++k) {
    const auto d = step(m, s, ws);
    EXPECT_FALSE(d.has_value()) << (d ? d->reason : "");
    if (d) break;
    r.worst_clearance = std::min(r.worst_clearance, *min_clearance(m, s.x, s.t));
  }
  for (const Vec3& v : s.v) r.final_max_speed = std::max(r.final_max_speed, v.norm());
  r.final_kinetic = kinetic_energy(m, s.v);
  r.x = s.x;
  return r;
}

TEST(Collisions, NoVertexInsideSphere) {
  const DropResult r = drop_on(sphere(Vec3(0, 0, 0), 0.15), 0.6, 0.3, 0.2);
  EXPECT_GE(r.worst_clearance, -kInsideTolerance);
  EXPECT_LT(r.worst_clearance, 1e-3) << "the cloth must have reached the sphere";
}

TEST(Collisions, NoVertexInsideCylinder) {
  const DropResult r = drop_on(cylinder(Vec3(0, 0, 0), Vec3(1, 0.3, 0), 0.1, 0.4), 0.6, 0.3, 0.15);
  EXPECT_GE(r.worst_clearance, -kInsideTolerance);
  EXPECT_LT(r.worst_clearance, 1e-3);
}

// Resting contact on a plane: the sheet lands, settles, stays on the plane and comes to
// rest (speeds decay instead of jittering).
TEST(Collisions, RestingContactOnPlaneIsStable) {
  const DropResult r = drop_on(plane(Vec3(0, 0, 0), Vec3(0, 0, 1)), 2.5, 0.5, 0.05);
  EXPECT_GE(r.worst_clearance, -kInsideTolerance);
  EXPECT_LT(r.final_max_speed, 1e-6);
  for (const Vec3& p : r.x) EXPECT_NEAR(p.z(), 0.0, 1e-9);
}

// Coulomb friction: a vertex sliding along a plane while pressed into it loses tangential
// speed mu * |normal speed| per contact, and stops when that exceeds its speed.
TEST(Collisions, CoulombFrictionOnProjection) {
  Model m;
  m.obstacles = {plane(Vec3::Zero(), Vec3(0, 0, 1))};
  m.obstacles[0].friction = 0.5;
  m.pinned = {0, 0};
  m.rest_uv = {Vec2(0, 0), Vec2(1, 0)};
  Vec3List x = {Vec3(0, 0, -0.01), Vec3(1, 0, -0.01)};
  Vec3List v = {Vec3(1.0, 0, -0.4), Vec3(0.1, 0, -0.4)};
  resolve_collisions(m, 0.0, x, v);
  EXPECT_DOUBLE_EQ(x[0].z(), 0.0);
  EXPECT_NEAR(v[0].x(), 1.0 - 0.5 * 0.4, 1e-15);
  EXPECT_DOUBLE_EQ(v[0].z(), 0.0);
  EXPECT_EQ(v[1], Vec3::Zero());
}

// A sphere moving up through a sheet held at its corners: still nothing inside.
TEST(Collisions, FastMovingSphereNeverLeavesVerticesInside) {
  Vec3List x;
  Model m = testing::grid_model(0.6, 0.6, 16, 16, 0.3, 7, &x);
  m.material = testing::test_material();
  m.gravity = Vec3(0, 0, -9.81);
  m.integrator = Integrator::SymplecticEuler;
  m.dt = 1e-4;
  m.pinned.assign(x.size(), 0);
  for (size_t i = 0; i < x.size(); ++i) {
    if (std::fabs(std::fabs(x[i].x()) - 0.3) < 1e-12 && std::fabs(std::fabs(x[i].y()) - 0.3) < 1e-12) {
      m.pinned[i] = 1;
    }
  }
  Obstacle ball = sphere(Vec3(0, 0, -0.2), 0.1);
  ball.motion.velocity = Vec3(0, 0, 2.0);  // m/s
  m.obstacles = {ball};
  precompute_rest(m);
  State s;
  s.x = x;
  s.v.assign(x.size(), Vec3::Zero());
  Workspace ws;
  for (int k = 0; k < 2000; ++k) {  // 0.2 s: the sphere goes from z = -0.2 to 0.2 m
    ASSERT_FALSE(step(m, s, ws).has_value()) << "step " << k;
    ASSERT_GE(*min_clearance(m, s.x, s.t), -kInsideTolerance) << "step " << k;
  }
  double top = -INFINITY;
  for (const Vec3& p : s.x) top = std::max(top, p.z());
  EXPECT_GT(top, 0.25) << "the sphere must have lifted the sheet";
}

}  // namespace
}  // namespace tissu
