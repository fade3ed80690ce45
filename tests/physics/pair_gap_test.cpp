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

// Two separate triangles with these rest coordinates (m), only for the self barrier's
// thickness and ids 0-3.
Model two_pieces(const Vec2List& rest_uv, const std::vector<Tri>& triangles) {
  Model m;
  m.rest_uv = rest_uv;
  m.triangles = triangles;
  m.material = *material_preset("cotton");
  m.dt = 1.0 / 60.0;
  m.implicit.contact = ContactModel::Barrier;
  m.self_collision = SelfCollision{kThickness, 0.0};
  precompute_rest(m);
  return m;
}

Model two_pieces() {
  return two_pieces(
      {Vec2(0, 0), Vec2(0.1, 0), Vec2(0, 0.1), Vec2(1, 0), Vec2(1.02, 0), Vec2(1, 0.02)},
      {Tri(0, 1, 2), Tri(3, 4, 5)});
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

// Two pieces whose edges 0-1 and 2-3 are both 2 cm long at rest.
Model two_edges() {
  return two_pieces(
      {Vec2(0, 0), Vec2(0.02, 0), Vec2(1, 0), Vec2(1.02, 0), Vec2(0, 0.02), Vec2(1, 0.02)},
      {Tri(0, 1, 4), Tri(2, 3, 5)});
}

// Edge 0-1 along x; edge 2-3 above it (gap about d), turned by `degrees` about z and
// shifted across by `across` (m), each point nudged by up to `nudge` (m; 0: none).
Vec3List crossing_edges(double degrees, double across, double d, std::mt19937* rng = nullptr,
                        double nudge = 0.0) {
  const double a = degrees * M_PI / 180.0, h = kThickness + d;
  const Vec3 centre(0.01, across, h), half(0.01 * std::cos(a), 0.01 * std::sin(a), 0.0);
  Vec3List x = {Vec3(0, 0, 0), Vec3(0.02, 0, 0), centre - half, centre + half};
  if (rng) {
    std::uniform_real_distribution<double> shift(-nudge, nudge);
    for (Vec3& p : x) p += Vec3(shift(*rng), shift(*rng), 0.5 * shift(*rng));
  }
  return x;
}

// The angle between the edges below which the pair is mollified, degrees: c = |e0 x e1|^2
// reaches eps_x at sin^2(a) = eps_x / (|e0|^2 |e1|^2), both edges 2 cm long.
double limit_degrees(const SelfBarrier& self, const std::array<int, 4>& ids) {
  const PairGap g = self.gap_of_vertices(ids, true, crossing_edges(10.0, 0.0, 1e-3));
  return std::asin(std::sqrt(g.cross_limit) / (0.02 * 0.02)) * 180.0 / M_PI;
}

// Nearly parallel edges within dhat: the gradient of m(c) b(gap) matches central
// differences of that energy, and its exact second derivative differences of the gradient,
// whichever features the closest points lie on.
TEST(PairGap, MollifiedBarrierMatchesDifferences) {
  const Model m = two_edges();
  SelfBarrier self;
  self.begin(m);
  const double dhat = 0.002, kappa = 50.0;  // m, kg/s^2
  const std::array<int, 4> ids = {0, 1, 2, 3};
  const auto energy = [&](const Vec3List& y) {
    const PairGap g = self.gap_of_vertices(ids, true, y);
    return edge_mollifier(g) * barrier_energy(g.d, dhat, kappa);
  };
  const auto gradient = [&](const Vec3List& y) {
    const PairGap g = self.gap_of_vertices(ids, true, y);
    return mollified_gradient(g, barrier_energy(g.d, dhat, kappa),
                              barrier_derivative(g.d, dhat, kappa));
  };
  // Edges within half the mollifier's angle, nudged by 3% of it at most, shifted
  // across by up to 1.2 times the shift that still puts the lines' crossing within both
  // edges: the closest points on their interiors, or at an end of one or both.
  const double limit = limit_degrees(self, ids) * M_PI / 180.0;  // rad
  ASSERT_GT(limit, 0.0);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> turn(0.0, 0.5 * limit), unit(-1.0, 1.0);
  std::uniform_real_distribution<double> gap(4e-4, 1.6e-3);
  int seen[3] = {0, 0, 0};  // by free parameters
  for (int trial = 0; trial < 300; ++trial) {
    const double a = turn(rng);
    const Vec3List x = crossing_edges(a * 180.0 / M_PI, 1.2 * unit(rng) * 0.01 * std::tan(a),
                                      gap(rng), &rng, 0.03 * limit * 0.02);
    const PairGap g = self.gap_of_vertices(ids, true, x);
    if (g.d < 2e-4 || g.d > dhat - 2e-4) continue;
    ASSERT_TRUE(is_mollified(g)) << "trial " << trial;
    const double mollifier = edge_mollifier(g);
    ASSERT_GT(mollifier, 0.0);
    ASSERT_LT(mollifier, 1.0);
    ++seen[g.params];
    PairVector fd_gradient;
    const double e = 1e-9;
    for (int c = 0; c < 12; ++c) {
      Vec3List plus = x, minus = x;
      plus[c / 3][c % 3] += e;
      minus[c / 3][c % 3] -= e;
      fd_gradient[c] = (energy(plus) - energy(minus)) / (2 * e);
    }
    const PairVector grad = gradient(x);
    EXPECT_LT((grad - fd_gradient).norm(), 1e-5 * grad.norm()) << "trial " << trial;
    const PairMatrix h = mollified_hessian(g, barrier_energy(g.d, dhat, kappa),
                                           barrier_derivative(g.d, dhat, kappa),
                                           barrier_second_derivative(g.d, dhat, kappa), false);
    const PairMatrix fd = differences(x, gradient, 1e-9);
    EXPECT_LT((h - fd).norm(), 1e-5 * h.norm())
        << "trial " << trial << ", " << g.params << " free parameters";
    EXPECT_LT((h - h.transpose()).norm(), 1e-12 * h.norm());
  }
  for (int p = 0; p < 3; ++p) EXPECT_GT(seen[p], 5) << p << " free parameters";
}

// Turning one edge through parallel: the mollified barrier falls smoothly to zero there,
// equals the plain barrier from eps_x on, and its projected Hessian is positive
// semi-definite with pinned vertices' rows and columns zero.
TEST(PairGap, MollifierTakesTheBarrierToZeroAtParallel) {
  const Model m = two_edges();
  SelfBarrier self;
  self.begin(m);
  const double dhat = 0.002, kappa = 50.0;  // m, kg/s^2
  const std::array<int, 4> ids = {0, 1, 2, 3};
  const auto at = [&](double degrees) {
    return self.gap_of_vertices(ids, true, crossing_edges(degrees, 0.0, 1e-3, nullptr));
  };
  const double limit = limit_degrees(self, ids);
  EXPECT_EQ(edge_mollifier(at(0.0)), 0.0);
  // m(c) = 2 r - r^2 with r = c / eps_x = sin^2(a) / sin^2(limit) here.
  const double sin_limit = std::sin(limit * M_PI / 180.0);
  for (double share : {0.2, 0.5, 0.9}) {
    const double r = std::pow(std::sin(share * limit * M_PI / 180.0) / sin_limit, 2);
    EXPECT_NEAR(edge_mollifier(at(share * limit)), r * (2.0 - r), 1e-9) << share;
  }
  // Beyond eps_x nothing changes.
  const PairGap wide = at(5.0 * limit);
  EXPECT_FALSE(is_mollified(wide));
  EXPECT_EQ(edge_mollifier(wide), 1.0);
  const double slope = barrier_derivative(wide.d, dhat, kappa);
  const double curvature = barrier_second_derivative(wide.d, dhat, kappa);
  EXPECT_EQ(mollified_hessian(wide, 0.0, slope, curvature, true),
            gap_function_hessian(wide, slope, curvature, true));
  // The slope of m(c) at eps_x is zero: the energy has no kink where the mollifier ends.
  const PairGap below = at(limit * (1 - 1e-4)), above = at(limit * (1 + 1e-4));
  EXPECT_NEAR(edge_mollifier(below), 1.0, 1e-7);
  // Projected, with vertex 1 pinned.
  const bool fixed[4] = {false, true, false, false};
  const PairGap g = at(0.5 * limit);
  const PairMatrix psd =
      mollified_hessian(g, barrier_energy(g.d, dhat, kappa), barrier_derivative(g.d, dhat, kappa),
                        barrier_second_derivative(g.d, dhat, kappa), true, fixed);
  const Eigen::SelfAdjointEigenSolver<PairMatrix> eig(psd);
  EXPECT_GE(eig.eigenvalues()[0], -1e-9 * eig.eigenvalues()[11]);
  EXPECT_GT(eig.eigenvalues()[11], 0.0);
  EXPECT_EQ(psd.middleRows<3>(3).norm(), 0.0);
  EXPECT_EQ(psd.middleCols<3>(3).norm(), 0.0);
  EXPECT_EQ(edge_mollifier(above), 1.0);
}

}  // namespace
}  // namespace tissu
