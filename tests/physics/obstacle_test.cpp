// Obstacles: exact signed distances, no vertex inside after any step, stable resting
// contact, friction.
#include <gtest/gtest.h>

#include "collision/closed_surface.h"
#include "collision/test_surfaces.h"
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

namespace tissu {
namespace {

std::shared_ptr<const ClosedSurface> surface_of(const testing::SurfaceData& s) {
  return std::make_shared<const ClosedSurface>(s.vertices, s.triangles, "test surface");
}

Obstacle mesh_obstacle(const testing::SurfaceData& s) {
  Obstacle o;
  o.kind = ObstacleKind::Mesh;
  o.surface = surface_of(s);
  o.center = o.surface->bounds().center();
  return o;
}

// A box mesh turned 90 degrees about z between two keyframes and moved: distances,
// normals and velocities are those of the box carried rigidly.
TEST(MeshObstacle, KeyframedBoxTurnsAndMoves) {
  Obstacle box = mesh_obstacle(testing::box_surface(Vec3(-0.5, -0.1, -0.1), Vec3(0.5, 0.1, 0.1)));
  Keyframe start, end;
  start.time = 1.0;
  end.time = 2.0;
  end.translation = Vec3(0, 0, 1.0);
  end.rotation = Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 2, Vec3::UnitZ()));
  box.motion.keyframes = {start, end};
  Vec3 n;
  // Before the first keyframe: as given; the long side along x.
  EXPECT_NEAR(box.signed_distance(Vec3(0.7, 0, 0), 0.5, &n), 0.2, 1e-15);
  EXPECT_TRUE(box.velocity(0.5).isZero());
  // Half way: turned 45 degrees, moved up 0.5 m; a point along the turned long axis.
  const Vec3 diagonal = Vec3(1, 1, 0).normalized();
  EXPECT_NEAR(box.signed_distance(Vec3(0, 0, 0.5) + 0.7 * diagonal, 1.5, &n), 0.2, 1e-12);
  EXPECT_TRUE(n.isApprox(diagonal, 1e-12));
  EXPECT_TRUE(box.velocity(1.5).isApprox(Vec3(0, 0, 1.0), 1e-12));
  EXPECT_TRUE(box.angular_velocity(1.5).isApprox(Vec3(0, 0, M_PI / 2), 1e-12));
  // After the last keyframe: held, the long side along y.
  EXPECT_NEAR(box.signed_distance(Vec3(0, 0.7, 1.0), 3.0, &n), 0.2, 1e-12);
  EXPECT_NEAR(box.signed_distance(Vec3(0.7, 0, 1.0), 3.0, &n), 0.6, 1e-12);
  EXPECT_TRUE(box.angular_velocity(3.0).isZero());
  EXPECT_TRUE(box.carried(Vec3(0.5, 0, 0), 3.0).isApprox(Vec3(0, 0.5, 1.0), 1e-12));
}

// Motion is judged by the pose: keyframes that repeat one pose do not move an obstacle,
// and a keyframed one moves only between keyframes whose poses differ.
TEST(ObstacleMotion, MovesOnlyWhereThePoseChanges) {
  ObstacleMotion m;
  EXPECT_FALSE(m.moves());
  Keyframe a, b, c;
  b.time = 1.0;
  c.time = 2.0;
  m.keyframes = {a, b};
  EXPECT_FALSE(m.moves());
  b.rotation = Eigen::Quaterniond(-1.0, 0.0, 0.0, 0.0);  // the same pose, written as -q
  m.keyframes = {a, b};
  EXPECT_FALSE(m.moves());
  c.translation = Vec3(0.0, 0.0, 0.1);
  m.keyframes = {a, b, c};
  EXPECT_TRUE(m.moves());
  EXPECT_FALSE(m.moves_between(0.0, 0.9));
  EXPECT_TRUE(m.moves_between(0.9, 1.0));  // its velocity at 1.0 is the next segment's
  EXPECT_TRUE(m.moves_between(0.9, 1.1));
  EXPECT_FALSE(m.moves_between(2.0, 3.0));
  c.translation = Vec3::Zero();
  c.rotation = Eigen::Quaterniond(Eigen::AngleAxisd(0.1, Vec3::UnitZ()));
  m.keyframes = {a, b, c};
  EXPECT_TRUE(m.moves_between(1.5, 1.6));
  b.translation = c.translation = Vec3(0.3, 0.0, 0.0);  // held still away from the start
  b.rotation = c.rotation;
  m.keyframes = {b, c};
  EXPECT_FALSE(m.moves());
  m.keyframes.clear();
  m.period = 1.0;
  m.amplitude = Vec3(0.1, 0.0, 0.0);
  EXPECT_TRUE(m.moves_between(5.0, 5.1));
  m = ObstacleMotion{};
  m.velocity = Vec3(0.0, 0.0, 1e-3);
  EXPECT_TRUE(m.moves());
}

// Dropped from several heights with several frictions, so that the cloth meets the box's
// edges and corners in different ways: the collision stage's impulses at the edges must
// not leave a vertex inside (from 0.1 m with friction 0.6 one ended 2.2e-6 m inside).
TEST(MeshObstacle, NoVertexInsideAMeshBox) {
  for (double height : {0.05, 0.1, 0.13}) {
    for (double friction : {0.3, 0.6}) {
      SCOPED_TRACE(::testing::Message() << "height " << height << " m, friction " << friction);
      const DropResult r = drop_on(
          mesh_obstacle(testing::box_surface(Vec3(-0.2, -0.2, -0.3), Vec3(0.1, 0.15, 0.0))), 0.6,
          friction, height);
      EXPECT_GE(r.worst_clearance, -kInsideTolerance);
      EXPECT_LT(r.worst_clearance, 1e-3) << "the cloth must have reached the box";
    }
  }
}

// A sheet dropped on a sphere meshed with 5120 triangles ends like the one dropped on the
// analytic sphere, both with a contact thickness of 3 mm. The analytic sphere meets cloth
// vertices only, so the cloth's 3.75 cm triangles sag up to 1.2 mm towards it between
// them; the meshed one also holds the triangles out of its vertices and edges, so the
// cloth may rest up to that much higher. Tolerances:
//   - no vertex closer to the centre than R + thickness - sagitta (0.17 mm): the meshed
//     surface lies between the sphere and its sagitta inside it;
//   - the fold pattern of a drape is a buckling that small changes decide (shrinking the
//     analytic sphere by the sagitta moves vertices by 1.6 cm on average, 7 cm at most),
//     so vertex positions are not compared; aggregate measures are, within twice how far
//     they move on the analytic sphere when its thickness grows by 0.6 or 1.2 mm (up to
//     the sag): centroid 6.3 mm -> 12 mm; share of vertices within 5.5 mm of the sphere
//     5.2 points -> 10 points; mean horizontal distance from the axis 3.4 mm -> 7 mm.
struct DrapeShape {
  Vec3 centroid = Vec3::Zero();
  double touching = 0, spread = 0, innermost = INFINITY;
};

DrapeShape shape_of(const DropResult& r, double radius) {
  DrapeShape d;
  const double n = static_cast<double>(r.x.size());
  for (const Vec3& p : r.x) {
    d.centroid += p / n;
    d.touching += (p.norm() < radius + 5.5e-3) / n;
    d.spread += p.head<2>().norm() / n;
    d.innermost = std::min(d.innermost, p.norm());
  }
  return d;
}

TEST(MeshObstacle, FineSphereMatchesTheAnalyticSphere) {
  constexpr double kRadius = 0.15, kThickness = 0.003;
  const testing::SurfaceData s = testing::icosphere(4, kRadius);
  double sagitta = 0;
  for (const Tri& t : s.triangles) {
    const Vec3 c = (s.vertices[t[0]] + s.vertices[t[1]] + s.vertices[t[2]]) / 3.0;
    sagitta = std::max(sagitta, kRadius - c.norm());
  }
  ASSERT_LT(sagitta, 2e-4);
  Obstacle analytic_sphere = sphere(Vec3::Zero(), kRadius), meshed_sphere = mesh_obstacle(s);
  analytic_sphere.thickness = meshed_sphere.thickness = kThickness;
  const DropResult analytic = drop_on(analytic_sphere, 0.5, 0.3, 0.2);
  const DropResult meshed = drop_on(meshed_sphere, 0.5, 0.3, 0.2);
  EXPECT_GE(meshed.worst_clearance, -kInsideTolerance);
  const DrapeShape a = shape_of(analytic, kRadius), m = shape_of(meshed, kRadius);
  EXPECT_GE(m.innermost, kRadius + kThickness - sagitta - 1e-12);
  EXPECT_LT((m.centroid - a.centroid).norm(), 0.012);
  EXPECT_NEAR(m.touching, a.touching, 0.10);
  EXPECT_NEAR(m.spread, a.spread, 0.007);
  EXPECT_GT(a.touching, 0.05);  // both rest on the sphere
  EXPECT_GT(m.touching, 0.05);
}

}  // namespace
}  // namespace tissu
