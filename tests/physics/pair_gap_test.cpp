// The second derivative of a barrier pair's gap (pair_gap.h) against central differences
// of its gradient, for point-triangle and edge-edge pairs between pieces of cloth in every
// closest-point region (face, edge, corner; edge interiors and ends), the barrier's Hessian
// built on it, and the projection to positive semi-definite.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <array>
#include <cmath>
#include <random>

#include "physics/barrier_contact.h"
#include "physics/materials.h"
#include "physics/membrane.h"
#include "physics/pair_gap.h"
#include "physics/self_barrier.h"

namespace tissu {
namespace {

constexpr double kThickness = 0.003;  // m

// Two separate triangles, only for the self barrier's thickness and ids 0-3.
Model two_pieces() {
  Model m;
  m.rest_uv = {Vec2(0, 0), Vec2(0.1, 0), Vec2(0, 0.1), Vec2(1, 0), Vec2(1.02, 0), Vec2(1, 0.02)};
  m.triangles = {Tri(0, 1, 2), Tri(3, 4, 5)};
  m.material = *material_preset("cotton");
  m.dt = 1.0 / 60.0;
  m.implicit.contact = ContactModel::Barrier;
  m.self_collision = SelfCollision{kThickness, 0.0};
  precompute_rest(m);
  return m;
}

// The nearest positive semi-definite matrix, by the full eigen-decomposition.
PairMatrix projected(const PairMatrix& m) {
  const Eigen::SelfAdjointEigenSolver<PairMatrix> eig(m);
  return eig.eigenvectors() * eig.eigenvalues().cwiseMax(0.0).asDiagonal() *
         eig.eigenvectors().transpose();
}

// The gap's own second derivative, d^2 r / d x^2 (1/m).
PairMatrix distance_hessian(const PairGap& g) { return gap_function_hessian(g, 1.0, 0.0, false); }

Eigen::Matrix<double, 12, 1> gradient_of(const PairGap& g) {
  Eigen::Matrix<double, 12, 1> out = Eigen::Matrix<double, 12, 1>::Zero();
  for (int k = 0; k < g.count; ++k) out.segment<3>(3 * k) = g.weights[k] * g.normal;
  return out;
}

// Central differences of `gradient(x)` (12) in the four points' coordinates.
template <typename Gradient>
PairMatrix differences(const Vec3List& x, Gradient gradient, double e) {
  PairMatrix out;
  for (int c = 0; c < 12; ++c) {
    Vec3List plus = x, minus = x;
    plus[c / 3][c % 3] += e;
    minus[c / 3][c % 3] -= e;
    out.col(c) = (gradient(plus) - gradient(minus)) / (2 * e);
  }
  return out;
}

// Random pairs about 1-3 cm apart: the Hessian of the distance (the gap's) matches central
// differences of the gradient w (x) n, in every region the closest points fall in.
TEST(PairGap, DistanceHessianMatchesDifferencesOfTheGradient) {
  const Model m = two_pieces();
  SelfBarrier self;
  self.begin(m);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> spread(-0.03, 0.03);
  const std::array<int, 4> ids = {0, 1, 2, 3};
  int seen[2][3] = {{0, 0, 0}, {0, 0, 0}};  // [edge_edge][free parameters]
  for (int trial = 0; trial < 400; ++trial) {
    Vec3List x(4);
    for (Vec3& p : x) p = Vec3(spread(rng), spread(rng), spread(rng));
    for (bool edge_edge : {false, true}) {
      const PairGap g = self.gap_of_vertices(ids, edge_edge, x);
      if (g.distance < 0.005) continue;
      ++seen[edge_edge][g.params];
      const PairMatrix h = distance_hessian(g);
      const PairMatrix fd = differences(x, [&](const Vec3List& y) {
        return gradient_of(self.gap_of_vertices(ids, edge_edge, y));
      }, 1e-7);
      EXPECT_LT((h - fd).norm(), 1e-5 * (1.0 + h.norm()))
          << "trial " << trial << (edge_edge ? " edge-edge" : " point-triangle") << ", "
          << g.params << " free parameters\n" << h << "\n\n" << fd;
      EXPECT_LT((h - h.transpose()).norm(), 1e-12 * h.norm());
    }
  }
  for (int e = 0; e < 2; ++e) {
    for (int p = 0; p < 3; ++p) EXPECT_GT(seen[e][p], 5) << e << " " << p;
  }
}

// A point above a triangle's face: moving it along the face leaves the gap unchanged, so
// its own block of the Hessian is zero; turning the triangle under it is not.
TEST(PairGap, PointOverAFaceHasNoCurvatureOfItsOwn) {
  const Model m = two_pieces();
  SelfBarrier self;
  self.begin(m);
  const Vec3List x = {Vec3(0.02, 0.03, 0.004), Vec3(0, 0, 0), Vec3(0.1, 0, 0), Vec3(0, 0.1, 0)};
  const PairGap g = self.gap_of_vertices({0, 1, 2, 3}, false, x);
  ASSERT_EQ(g.params, 2);
  EXPECT_NEAR(g.d, 0.001, 1e-15);
  const PairMatrix h = distance_hessian(g);
  const Mat3 own = h.block<3, 3>(0, 0);
  const Eigen::Matrix<double, 3, 9> across = h.block<3, 9>(0, 3);
  EXPECT_LT(own.norm(), 1e-12);
  EXPECT_GT(across.norm(), 1.0);  // 1/m: the point against the turning face
}

// The barrier's Hessian is the derivative of its gradient b'(d) w (x) n, and indefinite
// where the face turns under the point; projected it is positive semi-definite and keeps
// the exact one's curvature along the gap's gradient, where that is positive.
TEST(PairGap, BarrierHessianMatchesDifferencesAndProjects) {
  const Model m = two_pieces();
  SelfBarrier self;
  self.begin(m);
  const double dhat = 0.002, kappa = 50.0;  // m, kg/s^2
  const std::array<int, 4> ids = {0, 1, 2, 3};
  const Vec3List x = {Vec3(0.021, 0.032, 0.0035), Vec3(0, 0, 0), Vec3(0.1, 0, 0.002),
                      Vec3(0, 0.1, -0.001)};
  const PairGap g = self.gap_of_vertices(ids, false, x);
  ASSERT_GT(g.d, 0.0);
  ASSERT_LT(g.d, dhat);
  const double slope = barrier_derivative(g.d, dhat, kappa);
  const double curvature = barrier_second_derivative(g.d, dhat, kappa);
  const PairMatrix h = gap_function_hessian(g, slope, curvature, false);
  const PairMatrix fd = differences(x, [&](const Vec3List& y) {
    const PairGap gy = self.gap_of_vertices(ids, false, y);
    return Eigen::Matrix<double, 12, 1>(barrier_derivative(gy.d, dhat, kappa) * gradient_of(gy));
  }, 1e-9);
  EXPECT_LT((h - fd).norm(), 1e-5 * h.norm());
  const Eigen::SelfAdjointEigenSolver<PairMatrix> exact(h);
  EXPECT_LT(exact.eigenvalues()[0], -1e-3 * exact.eigenvalues()[11]);
  const PairMatrix psd = gap_function_hessian(g, slope, curvature, true);
  const Eigen::SelfAdjointEigenSolver<PairMatrix> after(psd);
  EXPECT_GE(after.eigenvalues()[0], -1e-9 * after.eigenvalues()[11]);
  EXPECT_LT((psd - projected(h)).norm(), 1e-9 * h.norm());
  const Eigen::Matrix<double, 12, 1> n = gradient_of(g);
  EXPECT_GE(n.dot(psd * n), n.dot(h * n) * (1.0 - 1e-12));
}

// The projection taken in the span of the five vectors the Hessian is made of is the full
// eigen-decomposition's, with and without fixed vertices (rows and columns zero), for
// random pairs in every region and barrier slopes of both signs.
TEST(PairGap, ProjectionInFiveVectorsIsTheFullOne) {
  const Model m = two_pieces();
  SelfBarrier self;
  self.begin(m);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> spread(-0.03, 0.03), unit(-1.0, 1.0);
  const std::array<int, 4> ids = {0, 1, 2, 3};
  for (int trial = 0; trial < 200; ++trial) {
    Vec3List x(4);
    for (Vec3& p : x) p = Vec3(spread(rng), spread(rng), spread(rng));
    const bool fixed[4] = {trial % 5 == 1, trial % 7 == 2, false, trial % 3 == 0};
    for (bool edge_edge : {false, true}) {
      const PairGap g = self.gap_of_vertices(ids, edge_edge, x);
      const double slope = 100.0 * unit(rng), curvature = 1e4 * std::fabs(unit(rng));
      PairMatrix exact = gap_function_hessian(g, slope, curvature, false);
      for (int k = 0; k < 4; ++k) {
        if (!fixed[k]) continue;
        exact.middleRows<3>(3 * k).setZero();
        exact.middleCols<3>(3 * k).setZero();
      }
      EXPECT_LE((gap_function_hessian(g, slope, curvature, false, fixed) - exact).norm(),
                1e-12 * exact.norm());
      const PairMatrix psd = gap_function_hessian(g, slope, curvature, true, fixed);
      EXPECT_LE((psd - projected(exact)).norm(), 1e-9 * exact.norm())
          << "trial " << trial << (edge_edge ? " edge-edge" : " point-triangle");
    }
  }
}

}  // namespace
}  // namespace tissu
