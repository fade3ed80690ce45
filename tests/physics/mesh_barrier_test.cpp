// A mesh obstacle's corners and edges in the barrier model (mesh_barrier.h): which features
// take part, the pairs' gaps and first touches against closed forms, the impulses against
// finite differences of the potential, and a sheet dropped on a box mesh at 1/60 s that its
// edges never cut.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>

#include "collision/closed_surface.h"
#include "collision/crossings.h"
#include "collision/test_surfaces.h"
#include "physics/barrier_contact.h"
#include "physics/diagnostics.h"
#include "physics/membrane.h"
#include "physics/step.h"
#include "physics/system_matrix.h"
#include "barrier_checks.h"
#include "strip_checks.h"
#include "test_meshes.h"

namespace tissu {
namespace {

constexpr double kThickness = 0.002;  // m
const Vec3 kLow(-0.15, -0.15, -0.2), kHigh(0.15, 0.15, 0.0);  // the box, m

Obstacle box_obstacle() { return testing::mesh_box(kLow, kHigh, kThickness, 0.0); }

// One cloth triangle (rest edges of 4 cm) placed at x.
Model one_triangle(const Vec3List& x) {
  Model m;
  m.rest_uv = {Vec2(0, 0), Vec2(0.04, 0), Vec2(0, 0.04)};
  m.triangles = {Tri(0, 1, 2)};
  m.material = *material_preset("cotton");
  m.material.bending = 0.0;
  m.dt = 1.0 / 60.0;
  m.implicit.contact = ContactModel::Barrier;
  precompute_rest(m);
  m.obstacles.push_back(box_obstacle());
  (void)x;
  return m;
}

TEST(MeshBarrier, FlatEdgesOfAFaceTakeNoPart) {
  // A triangle 1 mm above the middle of the top face, over the face's diagonal edge and far
  // from its corners and its sharp edges: no pair.
  const Vec3List x = {Vec3(-0.02, -0.02, 0.001), Vec3(0.02, -0.02, 0.001), Vec3(0.0, 0.03, 0.001)};
  const Model m = one_triangle(x);
  MeshFeatureBarrier pairs;
  pairs.begin(m, 0.0, 0.0);
  ASSERT_TRUE(pairs.active());
  pairs.find_pairs(x, x, 0.01);
  EXPECT_EQ(pairs.num_pairs(), 0);
  // The same triangle over a corner meets the corner and the three edges that end there
  // (each against the triangle's edges it may come near).
  Vec3List over = x;
  for (Vec3& p : over) p += Vec3(0.15, 0.15, 0.0);
  pairs.find_pairs(over, over, 0.01);
  EXPECT_GT(pairs.num_pairs(), 0);
}

// A ball of 1280 facets (radius 0.12 m, its edges bent by about 0.1 rad) under cloth with
// edges up to 5.7 cm: with a 3 mm thickness no cloth edge spanning one ball edge can dip
// through the surface while its ends keep the thickness (L theta / 4 < T), and no feature
// takes part (the least bend counted is 2 T / L = 0.106 rad); with a thickness of 1
// micrometre every edge does.
TEST(MeshBarrier, GentlyBentEdgesTakePartOnlyUnderAThinLayer) {
  const testing::SurfaceData ball = testing::icosphere(3, 0.12);
  const Vec3List x = {Vec3(0, 0, 0.2), Vec3(0.04, 0, 0.2), Vec3(0, 0.04, 0.2)};
  Model m = one_triangle(x);
  m.obstacles[0].surface =
      std::make_shared<const ClosedSurface>(ball.vertices, ball.triangles, "test ball");
  m.obstacles[0].center = Vec3::Zero();
  MeshFeatureBarrier pairs;
  m.obstacles[0].thickness = 0.003;
  pairs.begin(m, 0.0, 0.0);
  EXPECT_FALSE(pairs.active());
  m.obstacles[0].thickness = 1e-6;
  pairs.begin(m, 0.0, 0.0);
  EXPECT_TRUE(pairs.active());
}

TEST(MeshBarrier, CornerUnderATriangleGivesTheGapPastTheThickness) {
  const double h = 0.005;  // m above the corner (0.15, 0.15, 0)
  const Vec3List x = {Vec3(0.13, 0.13, h), Vec3(0.18, 0.14, h), Vec3(0.14, 0.18, h)};
  const Model m = one_triangle(x);
  MeshFeatureBarrier pairs;
  pairs.begin(m, 0.0, 0.0);
  pairs.find_pairs(x, x, 0.01);
  double smallest = INFINITY;
  pairs.for_each_gap(x, [&](const PairGap& g) {
    if (g.d < smallest - 1e-15) {
      smallest = g.d;
      if (g.count == 3) {
        EXPECT_NEAR(g.normal.z(), 1.0, 1e-12);  // straight up from the corner
        EXPECT_NEAR(g.weights[0] + g.weights[1] + g.weights[2], 1.0, 1e-12);
      }
    }
  });
  EXPECT_NEAR(smallest, h - kThickness, 1e-12);

  // Moving down by 2 h over the step, the triangle reaches the thickness at t = (h -
  // thickness) / (2 h); the advancement stops at or a little before it.
  Vec3List u(3, Vec3(0.0, 0.0, -2.0 * h));
  pairs.find_pairs(x, Vec3List{x[0] + u[0], x[1] + u[1], x[2] + u[2]}, 0.01);
  const double touch = (h - kThickness) / (2.0 * h);
  const double t = pairs.first_touch(x, u);
  EXPECT_LE(t, touch * (1.0 + 1e-12));
  EXPECT_GT(t, touch - 1e-3 * (h - kThickness) / (2.0 * h));
}

TEST(MeshBarrier, ClothEdgeAcrossABoxEdgeTouchesItWhenTheGapCloses) {
  // A triangle whose edge 0-1 crosses the box's top edge along y at x = 0.15, 4 mm above it,
  // and whose third corner lies higher (so the edge is the nearest part); it moves toward the
  // box's edge along (-1, 0, -2) / sqrt 5.
  const double h = 0.004;
  const Vec3List x = {Vec3(0.15, -0.02, h), Vec3(0.15, 0.02, h), Vec3(0.17, 0.0, h + 0.03)};
  const Model m = one_triangle(x);
  MeshFeatureBarrier pairs;
  pairs.begin(m, 0.0, 0.0);
  const Vec3 dir = Vec3(-1.0, 0.0, -2.0).normalized();
  Vec3List u(3, 0.01 * dir), to = x;
  for (int i = 0; i < 3; ++i) to[i] += u[i];
  pairs.find_pairs(x, to, 0.01);
  double smallest = INFINITY;
  pairs.for_each_gap(x, [&](const PairGap& g) { smallest = std::min(smallest, g.d); });
  EXPECT_NEAR(smallest, h - kThickness, 1e-12);
  // The edge's distance to the box's edge (along y at x = 0.15, z = 0) as it moves is
  // |(0, h) + s (-1, -2) / sqrt 5| in (x, z), s = 0.01 t m: the first s where it reaches
  // the thickness, s^2 - (4 / sqrt 5) h s + h^2 = thickness^2.
  const double a = 1.0, b = -4.0 * h / std::sqrt(5.0), c = h * h - kThickness * kThickness;
  const double s = (-b - std::sqrt(b * b - 4 * a * c)) / (2 * a);
  const double touch = s / 0.01;
  ASSERT_LT(touch, 1.0);
  const double t = pairs.first_touch(x, u);
  EXPECT_LE(t, touch);
  EXPECT_GT(t, touch - 1e-3);
}

// A box rising by 6 mm over the step under a still triangle 5 mm above its corner: the
// pair starts 3 mm apart (past the 2 mm thickness) and, measured in the box's frame, touches
// halfway through the step, although at the step's end the corner is above the triangle.
// Measured against the box where it ends the step, the pair is already crossed and left out.
TEST(MeshBarrier, MovingBoxIsMetInItsOwnFrameOverTheStep) {
  const double h = 0.005, dt = 1.0 / 60.0, rise = 0.006;  // m, s, m
  const Vec3List x = {Vec3(0.13, 0.13, h), Vec3(0.18, 0.14, h), Vec3(0.14, 0.18, h)};
  Model m = one_triangle(x);
  m.obstacles[0].motion.velocity = Vec3(0.0, 0.0, rise / dt);
  MeshFeatureBarrier pairs;
  pairs.begin(m, 0.0, dt);
  pairs.find_pairs(x, x, 0.01, /*from_start=*/false);
  EXPECT_GT(pairs.left_out(), 0);  // the corner, through the triangle
  pairs.find_pairs(x, x, 0.01, /*from_start=*/true);
  EXPECT_EQ(pairs.left_out(), 0);
  ASSERT_GT(pairs.num_pairs(), 0);
  int mesh = -1;
  const double t = pairs.first_touch_over_step(x, x, &mesh);
  const double touch = (h - kThickness) / rise;
  EXPECT_EQ(mesh, 0);
  EXPECT_LE(t, touch * (1.0 + 1e-12));
  EXPECT_GT(t, touch * (1.0 - 1e-3));
  EXPECT_TRUE(pairs.carried(0, x[0], 0.01).isApprox(x[0] + Vec3(0.0, 0.0, rise), 1e-12));
  const Vec3 far(0.0, 0.0, 0.5);  // m: 0.5 m above the box, not carried
  EXPECT_EQ(pairs.carried(0, far, 0.01), far);
}

// The barrier's step potential and impulses with the box's features: -impulse = d
// potential / dv (finite differences), and along a translation of the whole triangle along
// a pair's normal, the Hessian's second derivative is the potential's.
TEST(MeshBarrier, ImpulsesMatchFiniteDifferencesOfThePotential) {
  const Vec3List x = {Vec3(0.135, 0.138, 0.0035), Vec3(0.178, 0.141, 0.0042),
                      Vec3(0.139, 0.176, 0.0051)};
  Model m = one_triangle(x);
  m.implicit.barrier_distance = 0.004;  // m: the corner's pair acts, the vertices' too
  const double h = m.dt;
  BarrierContact contact;
  contact.begin(m, x, x, h, h, 0.0, h);
  ASSERT_TRUE(contact.enabled());
  Vec3List v(3, Vec3::Zero());
  Eigen::VectorXd dv = Eigen::VectorXd::Zero(9);
  EXPECT_EQ(contact.largest_step(v, dv), 1.0);  // finds the pairs about x
  double gap = 0.0;
  ASSERT_GT(contact.active(v, &gap), 0);
  ASSERT_GT(gap, 0.0);
  testing::expect_impulses_match_potential(contact, v);
  // Straight up, every distance (corner to face, vertices to the top face) grows at the
  // rate of the motion: the Gauss-Newton Hessian is exact along it.
  SystemMatrix system;
  system.plan(m);
  system.assemble(m, x, v, 0.0, h, true);
  Eigen::VectorXd before(9), after(9);
  Eigen::VectorXd up = Eigen::VectorXd::Zero(9);
  for (int i = 0; i < 3; ++i) up[3 * i + 2] = 1.0;
  system.matrix().multiply(up, before);
  contact.add_hessian(v, system);
  system.matrix().multiply(up, after);
  const double curvature = up.dot(after - before);  // kg*(m/s)^2 per (m/s)^2
  const double second = testing::potential_curvature(contact, v, up, 1e-5);
  EXPECT_NEAR(curvature, second, 1e-4 * std::fabs(second));
}

// Friction on the box's corner and edges: a triangle over the box's corner, 1 mm past the
// thickness, its vertices beyond dhat of the box, so that only the feature pairs touch it,
// sliding across the corner. The lagged friction's impulses are minus the gradient of the
// potential (finite differences), its matrix the potential's curvature along the slide, and
// it opposes the slide, at most mu times the pairs' normal impulse (the vertices take none).
TEST(MeshBarrier, FrictionOnCornersAndEdgesMatchesFiniteDifferencesAndOpposesTheSlide) {
  const Vec3List x = {Vec3(0.12, 0.17, kThickness + 0.001), Vec3(0.17, 0.12, kThickness + 0.001),
                      Vec3(0.19, 0.19, kThickness + 0.001)};
  const double mu = 0.4;
  Vec3List v(3, Vec3(0.05, -0.02, 0.0));  // m/s, across the corner
  Eigen::VectorXd rhs[2];
  for (int with = 0; with < 2; ++with) {
    Model m = one_triangle(x);
    m.implicit.barrier_distance = 0.004;  // m
    m.obstacles[0].friction = with ? mu : 0.0;
    const double h = m.dt;
    BarrierContact contact;
    contact.begin(m, x, x, h, h, 0.0, h);
    ASSERT_TRUE(contact.enabled());
    Eigen::VectorXd dv = Eigen::VectorXd::Zero(9);
    EXPECT_EQ(contact.largest_step(v, dv), 1.0);  // finds the pairs about x + h v
    int pairs = 0;
    ASSERT_GT(contact.active(v, nullptr, &pairs), 0);
    ASSERT_GT(pairs, 0);
    rhs[with] = Eigen::VectorXd::Zero(9);
    contact.add_impulses(v, rhs[with]);
    if (!with) continue;
    testing::expect_impulses_match_potential(contact, v);
    SystemMatrix system;
    system.plan(m);
    system.assemble(m, x, v, 0.0, h, true);
    Eigen::VectorXd slide = Eigen::VectorXd::Zero(9), before(9), after(9);
    for (int i = 0; i < 3; ++i) slide.segment<3>(3 * i) = Vec3(0.05, -0.02, 0.0).normalized();
    system.matrix().multiply(slide, before);
    contact.add_hessian(v, system);
    system.matrix().multiply(slide, after);
    const double curvature = slide.dot(after - before);
    const double second = testing::potential_curvature(contact, v, slide, 1e-5);
    EXPECT_NEAR(curvature, second, 1e-4 * std::fabs(second) + 1e-12);
  }
  // The friction's total impulse on the triangle: against the slide, horizontal, and at
  // most mu times the barrier's upward impulse (which the slide hardly changes).
  Vec3 friction = Vec3::Zero(), normal = Vec3::Zero();  // kg*m/s
  for (int i = 0; i < 3; ++i) {
    friction += Vec3(rhs[1].segment<3>(3 * i) - rhs[0].segment<3>(3 * i));
    normal += Vec3(rhs[0].segment<3>(3 * i));
  }
  std::printf("  friction impulse %.3g kg*m/s against a normal impulse %.3g\n", friction.norm(),
              normal.z());
  ASSERT_GT(normal.z(), 0.0);
  EXPECT_LT(friction.dot(v[0]) / (friction.norm() * v[0].norm()), -0.99);
  EXPECT_LE(friction.norm(), mu * normal.z() * 1.05);
  EXPECT_GE(friction.norm(), 0.5 * mu * normal.z());
}

// A coarse cotton sheet (5 cm cells) dropped 5 mm onto the box with backward Euler at
// 1/60 s drapes over its edges: at every step no cloth triangle crosses the box's (exact
// check) and no vertex is inside, and the barrier holds the box's edges by itself: the
// collision stage after the solve finds nothing to correct. Without the corner and edge
// pairs, the box's edges come within the thickness of the cloth's triangles between their
// vertices, and the stage pushes them off at every step (8,772 corrections in these 45
// steps under the constraints model, before its solve took the pairs). Under the
// constraints the vertices rest on the faces at the thickness, to rounding.
void expect_sheet_on_box_never_cut(ContactModel contact) {
  testing::Sheet s = testing::cotton_sheet(0.5, 10, Integrator::BackwardEuler, 1.0 / 60.0);
  s.model.implicit.contact = contact;
  s.model.obstacles.push_back(box_obstacle());
  for (Vec3& p : s.state.x) p.z() = kThickness + 0.005;
  const testing::SurfaceData box = testing::box_surface(kLow, kHigh);
  Workspace ws;
  double lowest_gap = INFINITY, strain = 0.0;
  int corrections = 0;
  for (int k = 0; k < 45; ++k) {
    ASSERT_FALSE(step(s.model, s.state, ws)) << "step " << k;
    corrections += ws.contact.proximities + ws.contact.impacts;
    const CrossingReport cut = crossings_between(s.state.x, s.model.triangles, box.vertices,
                                                 box.triangles, 1);
    ASSERT_FALSE(cut.any()) << "step " << k << ": cloth triangle " << cut.pairs[0].first
                            << " crosses the box's triangle " << cut.pairs[0].second;
    for (const Vec3& p : s.state.x) {
      Vec3 n;
      lowest_gap = std::min(lowest_gap, s.model.obstacles[0].signed_distance(p, s.state.t, &n));
    }
    strain = std::max(strain, max_principal_strain(s.model, s.state.x));
  }
  std::printf("  closest vertex %.3g m from the box, largest strain %.3g, %d stage corrections\n",
              lowest_gap, strain, corrections);
  EXPECT_GT(lowest_gap, kThickness - (contact == ContactModel::Constraints ? 1e-9 : 0.0));
  EXPECT_EQ(corrections, 0);
  // The sheet hangs over the edges: its corners fall well below the top face.
  double bottom = INFINITY;
  for (const Vec3& p : s.state.x) bottom = std::min(bottom, p.z());
  EXPECT_LT(bottom, -0.05);
  EXPECT_LT(strain, 0.05);
}

TEST(MeshBarrier, SheetDroppedOnAMeshBoxIsNeverCutByItsEdges) {
  expect_sheet_on_box_never_cut(ContactModel::Barrier);
}

TEST(MeshBarrier, SheetDroppedOnAMeshBoxIsNeverCutByItsEdgesWithTheConstraints) {
  expect_sheet_on_box_never_cut(ContactModel::Constraints);
}

}  // namespace
}  // namespace tissu
