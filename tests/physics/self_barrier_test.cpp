// The cloth against itself in the barrier model (self_barrier.h): gap gradients against
// finite differences, first touches against closed forms, which pairs take part, and the
// step's matrix with its blocks between two pieces of cloth against the potential.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "physics/barrier_contact.h"
#include "physics/membrane.h"
#include "physics/self_barrier.h"
#include "physics/system_matrix.h"
#include "barrier_checks.h"
#include "test_meshes.h"

namespace tissu {
namespace {

constexpr double kThickness = 0.003;  // m

// Two separate triangles, vertices 0-2 and 3-5, with these rest coordinates (m), in cotton
// without bending, with self-collision in the barrier.
Model two_pieces(const Vec2List& rest_uv) {
  Model m;
  m.rest_uv = rest_uv;
  m.triangles = {Tri(0, 1, 2), Tri(3, 4, 5)};
  m.material = *material_preset("cotton");
  m.material.bending = 0.0;
  m.dt = 1.0 / 60.0;
  m.implicit.contact = ContactModel::Barrier;
  m.self_collision = SelfCollision{kThickness, 0.0};
  precompute_rest(m);
  return m;
}

// Two separate triangles: a large one (10 cm legs) in the plane z = 0 and a small one
// (2 cm legs) above its middle at height z, each with its own fabric in (u, v).
Model two_triangles(double z, Vec3List* x) {
  Model m = two_pieces(
      {Vec2(0, 0), Vec2(0.1, 0), Vec2(0, 0.1), Vec2(1, 0), Vec2(1.02, 0), Vec2(1, 0.02)});
  *x = {Vec3(0, 0, 0), Vec3(0.1, 0, 0), Vec3(0, 0.1, 0),
        Vec3(0.02, 0.02, z), Vec3(0.04, 0.02, z), Vec3(0.02, 0.04, z)};
  return m;
}

// d gap / d x_k = w_k n for vertex-triangle and edge-edge pairs in general position.
TEST(SelfBarrier, GapGradientIsTheWeightedNormal) {
  Vec3List x;
  const Model m = two_triangles(0.01, &x);
  SelfBarrier self;
  self.begin(m);
  ASSERT_TRUE(self.active());
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> spread(-0.03, 0.03);
  for (int trial = 0; trial < 20; ++trial) {
    Vec3List p(4);
    for (Vec3& q : p) q = Vec3(spread(rng), spread(rng), spread(rng));
    for (bool edge_edge : {false, true}) {
      const std::array<int, 4> ids = {0, 1, 2, 3};
      const PairGap g = self.gap_of_vertices(ids, edge_edge, p);
      EXPECT_EQ(g.split, edge_edge ? 2 : 1);
      const double e = 1e-7;  // m
      for (int k = 0; k < 4; ++k) {
        for (int c = 0; c < 3; ++c) {
          Vec3List plus = p, minus = p;
          plus[k][c] += e;
          minus[k][c] -= e;
          const double slope = (self.gap_of_vertices(ids, edge_edge, plus).d -
                                self.gap_of_vertices(ids, edge_edge, minus).d) / (2 * e);
          EXPECT_NEAR(slope, g.weights[k] * g.normal[c], 1e-6)
              << "trial " << trial << (edge_edge ? " edge-edge" : " vertex-triangle")
              << " vertex " << k << " axis " << c;
        }
      }
    }
  }
}

// A small triangle falling straight onto a large one, parallel to it, touches it once
// they have fallen 1 cm - the thickness, at t = (0.01 - T) / 0.02 of a 2 cm path: the
// advancement's bound is exact there. A sideways drift as large as the fall makes the
// bound loose: the advancement then stops at or before the touch, once the gap may have
// shrunk to a tenth of its start, and not so close to the touch that a line search step
// of 0.9 of it could leave the pair within a hundredth of it (where the barrier's force
// would stall Newton).
TEST(SelfBarrier, FirstTouchOfAFallingTriangleIsWhereItsGapCloses) {
  Vec3List x;
  const Model m = two_triangles(0.01, &x);
  SelfBarrier self;
  self.begin(m);
  const double exact = (0.01 - kThickness) / 0.02;
  for (const Vec3& drift : {Vec3(0, 0, 0), Vec3(0.02, 0.01, 0)}) {
    Vec3List to = x;
    for (int i = 3; i < 6; ++i) to[i] += Vec3(0, 0, -0.02) + drift;
    self.find_pairs(x, to, 0.002);
    ASSERT_GT(self.num_pairs(), 0);
    const double t = self.first_touch(x, to);
    if (drift.isZero()) {
      EXPECT_NEAR(t, exact, 1e-12);
    } else {
      EXPECT_GE(t, 0.9 * exact);   // the gap at t is at most a tenth of its start
      EXPECT_LE(t, 0.99 * exact);  // and at least a hundredth
    }
  }
  // Two crossing edges, one 1 cm above the other and falling onto it: the gap closes at
  // (0.01 - T) / 0.02 as well.
  Vec3List y = {Vec3(-0.05, 0, 0), Vec3(0.05, 0, 0), Vec3(0, 0.1, 0),
                Vec3(0, -0.03, 0.01), Vec3(0, 0.03, 0.01), Vec3(0.04, 0.5, 0.01)};
  Vec3List to = y;
  for (int i = 3; i < 6; ++i) to[i].z() -= 0.02;
  const PairGap g = self.gap_of_vertices({0, 1, 3, 4}, true, y);
  EXPECT_NEAR(g.d, 0.01 - kThickness, 1e-12);
  self.find_pairs(y, to, 0.002);
  const double t = self.first_touch(y, to);
  EXPECT_LE(t, (0.01 - kThickness) / 0.02);
  EXPECT_GT(t, (0.01 - kThickness) / 0.02 - 1e-3);
  // Moving away: no touch.
  for (int i = 3; i < 6; ++i) to[i].z() = 0.05;
  self.find_pairs(y, to, 0.002);
  EXPECT_EQ(self.first_touch(y, to), 1.0);
}

// Neighbours in the fabric take no part: a flat sheet in its rest shape has no pair; the
// same sheet folded so that its halves lie 5 mm apart has many.
TEST(SelfBarrier, OnlyPiecesApartInTheFabricTakePart) {
  testing::Sheet s = testing::cotton_sheet(0.2, 10, Integrator::BackwardEuler, 1.0 / 60.0);
  s.model.self_collision = SelfCollision{kThickness, 0.0};
  const double dhat = 0.25 * mean_rest_edge(s.model);
  SelfBarrier self;
  self.begin(s.model);
  self.find_pairs(s.state.x, s.state.x, dhat);
  EXPECT_EQ(self.num_pairs(), 0);
  Vec3List folded = s.state.x;
  for (Vec3& p : folded) {
    if (p.x() > 0.0) p = Vec3(-p.x(), p.y(), kThickness + 0.002);
  }
  self.find_pairs(folded, folded, dhat);
  EXPECT_GT(self.num_pairs(), 50);
}

// The barrier of the small triangle resting above the large one: its impulses are minus
// the potential's gradient (finite differences), and the step's matrix, with the blocks
// between the two triangles applied by product, has the potential's second derivative
// along pulling the two apart (where the Gauss-Newton matrix is exact). Without those
// blocks it would be half as large.
TEST(SelfBarrier, MatrixBetweenTwoPiecesMatchesThePotential) {
  Vec3List x;
  Model m = two_triangles(kThickness + 0.0012, &x);
  m.implicit.barrier_distance = 0.002;  // m
  x[4].z() += 0.0002;  // a slight tilt: the three gaps differ
  const double h = m.dt;
  BarrierContact contact;
  contact.begin(m, x, x, h, h, 0.0, h);
  ASSERT_TRUE(contact.enabled());
  Vec3List v(6, Vec3::Zero());
  Eigen::VectorXd dv = Eigen::VectorXd::Zero(18);
  EXPECT_EQ(contact.largest_step(v, dv), 1.0);
  ASSERT_EQ(contact.active(v), 3);  // the small triangle's three corners
  testing::expect_impulses_match_potential(contact, v);
  SystemMatrix system;
  system.plan(m);
  system.assemble(m, x, v, 0.0, h, true);
  Eigen::VectorXd apart = Eigen::VectorXd::Zero(18), before(18), after(18);
  for (int i = 0; i < 3; ++i) apart[3 * i + 2] = -1.0;
  for (int i = 3; i < 6; ++i) apart[3 * i + 2] = 1.0;
  system.matrix().multiply(apart, before);
  contact.add_hessian(v, system);
  ASSERT_NE(contact.coupling(), nullptr);
  system.matrix().multiply(apart, after);
  const double within = apart.dot(after - before);
  contact.coupling()->add_product(apart, after);
  const double curvature = apart.dot(after - before);
  const double second = testing::potential_curvature(contact, v, apart, 1e-5);
  EXPECT_NEAR(curvature, second, 1e-4 * second);
  EXPECT_LT(within, 0.6 * second);
}


// Two equal triangles (2 cm legs) one over the other, the upper turned by 0.05 degrees
// and moving slowly: their edges lie nearly parallel, so the edge-edge pairs' barrier is mollified
// (pair_gap.h). The step's impulses are still minus the gradient of its potential, with
// the mollifier in both, and the mollified pairs lower that potential below the plain
// barrier's sum.
TEST(SelfBarrier, MollifiedEdgePairsKeepImpulsesAndPotentialTogether) {
  Model m = two_pieces(
      {Vec2(0, 0), Vec2(0.02, 0), Vec2(0, 0.02), Vec2(1, 0), Vec2(1.02, 0), Vec2(1, 0.02)});
  m.implicit.barrier_distance = 0.002;  // m
  const double turn = 0.05 * M_PI / 180.0, z = kThickness + 0.001;
  const Eigen::AngleAxisd about_z(turn, Vec3::UnitZ());
  const Vec3 centre(0.007, 0.007, 0.0);
  Vec3List x = {Vec3(0, 0, 0), Vec3(0.02, 0, 0), Vec3(0, 0.02, 0)};
  for (int i = 0; i < 3; ++i) x.push_back(centre + about_z * (x[i] - centre) + Vec3(0, 0, z));
  const double h = m.dt;
  BarrierContact contact;
  contact.begin(m, x, x, h, h, 0.0, h);
  ASSERT_TRUE(contact.enabled());
  const Vec3List v = {Vec3(0, 0, 0), Vec3(5e-4, 0, 0), Vec3(0, 0, 3e-4),
                      Vec3(0, 5e-4, 0), Vec3(0, 0, -4e-4), Vec3(3e-4, 0, 0)};  // m/s
  Eigen::VectorXd dv = Eigen::VectorXd::Zero(18);
  ASSERT_EQ(contact.largest_step(v, dv), 1.0);
  testing::expect_impulses_match_potential(contact, v);
  // The pairs at the step's end positions: some edge-edge ones are mollified.
  Vec3List end = x;
  for (int i = 0; i < 6; ++i) end[i] += h * v[i];
  SelfBarrier self;
  self.begin(m);
  self.find_pairs(end, end, 0.002);
  int mollified = 0;
  double plain = 0.0, with_mollifier = 0.0;
  self.for_each_gap(end, [&](const PairGap& g) {
    if (g.d <= 0.0 || g.d >= 0.002) return;
    mollified += is_mollified(g) ? 1 : 0;
    // kappa = m / dt^2, every vertex of the two equal triangles of the same mass.
    const double b = barrier_energy(g.d, 0.002, barrier_stiffness(m.mass[0], h));
    plain += b;
    with_mollifier += edge_mollifier(g) * b;
  });
  EXPECT_GE(mollified, 3);
  EXPECT_LT(with_mollifier, plain);
  EXPECT_NEAR(m.mass[0], m.mass[5], 1e-15);
  EXPECT_NEAR(contact.potential(v), with_mollifier, 1e-9 * plain)
      << "the potential holds the mollified pairs' energy";
}

// The large triangle lies on a plane at a gap of rounding, the small one on it just beyond
// the thickness. The initial guess of a step at rest pushes the large triangle out of the
// plane toward the gap where the barrier holds its weight, which is into the small one;
// its pairs would then be left out of the step, which ends with the layers within the
// thickness (a silk sheet folding on the ground at 1/30 s, docs/implicit.md). Instead the
// vertices of pairs whose paths touch start where the step starts: every pair the step
// takes is apart on its path to the guess, and none is left out.
TEST(SelfBarrier, GuessPushedOutOfAPlaneIntoALayerKeepsThatLayerApart) {
  Vec3List x;
  Model m = two_triangles(kThickness + 0.0002, &x);
  m.gravity = Vec3(0, 0, -9.81);
  m.implicit.barrier_distance = 0.004;  // m: the push out reaches up to 2 mm
  m.obstacles.push_back(testing::make_obstacle(ObstacleKind::Plane, Vec3(0, 0, -1e-7),
                                               Vec3::UnitZ(), 0.0, 0.0, 0.0));
  precompute_rest(m);
  const double h = m.dt;
  BarrierContact contact;
  contact.begin(m, x, x, h, h, 0.0, h);
  ASSERT_TRUE(contact.enabled());
  Vec3List weight(x.size());
  for (size_t i = 0; i < x.size(); ++i) weight[i] = m.mass[i] * *m.gravity;  // N
  Vec3List v(x.size(), Vec3::Zero());
  contact.make_feasible(v, v, [&]() -> const Vec3List& { return weight; });
  Vec3List end = x;
  for (size_t i = 0; i < x.size(); ++i) end[i] += h * v[i];
  SelfBarrier self;
  self.begin(m);
  self.find_pairs(x, end, contact.dhat());
  EXPECT_EQ(self.left_out(), 0);
  EXPECT_EQ(self.first_touch(x, end), 1.0);
  for (int i = 0; i < 3; ++i) EXPECT_GT(end[i].z(), -1e-7) << "vertex " << i << " below the plane";
  // Without the small triangle above, the same guess lifts the large one farther than the
  // small one lies beyond the thickness.
  Vec3List alone = x;
  for (int i = 3; i < 6; ++i) alone[i].z() += 0.1;
  BarrierContact lone;
  lone.begin(m, alone, alone, h, h, 0.0, h);
  Vec3List u(x.size(), Vec3::Zero());
  lone.make_feasible(u, u, [&]() -> const Vec3List& { return weight; });
  EXPECT_GT(h * u[0].z(), 0.0002);  // m: farther than the small triangle lies beyond T
}

}  // namespace
}  // namespace tissu
