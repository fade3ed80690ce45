// The scalar Cholesky preconditioner (physics/scalar_preconditioner.h), plain and
// block-scaled: positive definite on a projected system matrix, exact where its scalar
// model is, and PCG with it reaches the requested true residual. The implicit steps it
// gives are compared with the block factor's in implicit_test.cpp.
#include "physics/scalar_preconditioner.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "physics/bending.h"
#include "physics/materials.h"
#include "physics/membrane.h"
#include "physics/system_matrix.h"
#include "test_meshes.h"

namespace tissu {
namespace {

struct Projected {
  BlockSparseMatrix A;
  Eigen::MatrixXd dense;
  std::vector<uint8_t> pinned;  // (V)
};

// M - h df/dv - h^2 df/dx at h = 1/60 s of a stretched, bent, partly compressed sheet with
// bending (diagonal-only blocks), damping and two pinned vertices, the Jacobian projected,
// plus a barrier-like stiffness along a normal at a few vertices (1e4 times their mass per
// s^2 of the step).
Projected projected_system_matrix() {
  Vec3List x;
  Model m = testing::grid_model(0.12, 0.1, 5, 4, 0.3, 11, &x);
  m.material = *material_preset("linen");
  m.gravity = Vec3(0, 0, -9.81);
  m.air_damping = 0.7;  // N*s/m^3
  m.pinned.assign(x.size(), 0);
  m.pinned[0] = m.pinned[9] = 1;
  precompute_rest(m);
  m.bending = std::make_shared<const BendingModel>(
      build_bending(m.triangles, m.rest_uv, m.material.bending, m.material.bending_warp));
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> noise(-1.0, 1.0);
  Vec3List v(x.size());
  for (size_t i = 0; i < x.size(); ++i) {
    const double squeeze = i % 3 == 0 ? 0.9 : 1.03;  // some triangles compressed
    x[i] = Vec3(squeeze * x[i].x(), x[i].y(), 1.5 * x[i].x() * x[i].y()) +
           0.003 * Vec3(noise(rng), noise(rng), noise(rng));
    v[i] = 0.2 * Vec3(noise(rng), noise(rng), noise(rng));
  }
  const double h = 1.0 / 60.0;
  SystemMatrix system;
  system.assemble(m, x, v, 0.0, h, /*project_psd=*/true);
  for (int i : {3, 11, 17}) {
    const Vec3 n = Vec3(0.3, -0.2, 1.0).normalized();
    system.add_diagonal(i, 1e4 * m.mass[i] * n * n.transpose());
  }
  return {system.matrix(), system.matrix().to_dense(), m.pinned};
}

Eigen::VectorXd random_free_vector(const std::vector<uint8_t>& pinned, std::mt19937& rng) {
  std::normal_distribution<double> g;
  Eigen::VectorXd y(3 * pinned.size());
  for (Eigen::Index k = 0; k < y.size(); ++k) y[k] = pinned[k / 3] ? 0.0 : g(rng);
  return y;
}

TEST(LinearSolver, ScalarFactorsArePositiveDefiniteOnAProjectedSystemMatrix) {
  const Projected p = projected_system_matrix();
  ASSERT_GT(p.A.num_diagonal_blocks(), 0) << "bending's second ring is in the matrix";
  std::mt19937 rng(9);
  for (int trial = 0; trial < 10; ++trial) {
    const Eigen::VectorXd z = random_free_vector(p.pinned, rng);
    EXPECT_GT(z.dot(p.dense * z), 0.0) << "z^T A z";
  }
  for (bool scaled : {false, true}) {
    ScalarCholeskyPreconditioner P;
    ASSERT_TRUE(P.compute(p.A, scaled)) << "scaled " << scaled;
    for (int trial = 0; trial < 10; ++trial) {
      const Eigen::VectorXd r = random_free_vector(p.pinned, rng);
      const Eigen::VectorXd s = random_free_vector(p.pinned, rng);
      Eigen::VectorXd Pr, Ps;
      P.apply(r, Pr);
      P.apply(s, Ps);
      EXPECT_GT(r.dot(Pr), 0.0) << "r^T P^-1 r, scaled " << scaled;
      EXPECT_NEAR(s.dot(Pr), r.dot(Ps), 1e-12 * Pr.norm() * s.norm()) << "symmetric";
      for (size_t i = 0; i < p.pinned.size(); ++i) {
        if (p.pinned[i]) {
          EXPECT_EQ(Pr.segment<3>(3 * i).norm(), 0.0) << "pinned vertex " << i;
        }
      }
    }
  }
}

TEST(LinearSolver, PcgWithScalarFactorsReachesTheRequestedResidual) {
  const Projected p = projected_system_matrix();
  std::mt19937 rng(4);
  const Eigen::VectorXd b = random_free_vector(p.pinned, rng);
  CgWorkspace work;
  for (bool scaled : {false, true}) {
    ScalarCholeskyPreconditioner P;
    ASSERT_TRUE(P.compute(p.A, scaled));
    for (double tol : {1e-4, 1e-10}) {
      Eigen::VectorXd x = Eigen::VectorXd::Zero(b.size());
      const CgResult r = solve_pcg(p.A, P, b, tol, 1000, x, work);
      EXPECT_TRUE(r.converged) << "scaled " << scaled << ", tol " << tol;
      EXPECT_LE((b - p.dense * x).norm(), 1.01 * tol * b.norm()) << "true residual";
    }
  }
}

// A matrix with blocks A_ij = s_ij R_i R_j (R_i symmetric positive definite, s_ii = 1,
// S = (s_ij) positive definite) is exactly the block-scaled model: D_i^-1/2 = R_i^-1
// and the scaled blocks are s_ij I3. With every R_i = I it is the plain model. Either
// factor is then the inverse and PCG stops after one iteration.
TEST(LinearSolver, ScalarFactorsAreExactOnTheirOwnModel) {
  const int n = 12;
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<std::pair<int, int>> full;
  for (int i = 0; i < n; ++i) {
    for (int j : {i, (i + 1) % n, (i + 5) % n}) {
      full.emplace_back(i, j);
      full.emplace_back(j, i);
    }
  }
  for (bool scaled : {false, true}) {
    std::vector<Mat3> R(n, Mat3::Identity());
    if (scaled) {
      for (Mat3& r : R) {
        Mat3 B;
        for (int k = 0; k < 9; ++k) B(k) = u(rng);
        r = B * B.transpose() + 0.2 * Mat3::Identity();
      }
    }
    BlockSparseMatrix A;
    A.set_pattern(n, full);
    for (const auto& [i, j] : full) {
      const int lo = std::min(i, j), hi = std::max(i, j);
      // A diagonally dominant scalar coupling, symmetric in (i, j).
      const double s = i == j ? 1.0 : -0.12 - 0.01 * ((lo * 7 + hi * 3) % 5);
      Eigen::Map<Mat3>(A.block_values(A.find(i, j))) = s * R[i] * R[j];
    }
    ScalarCholeskyPreconditioner P;
    ASSERT_TRUE(P.compute(A, scaled));
    const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(3 * n, -1.0, 2.0);
    CgWorkspace work;
    Eigen::VectorXd x = Eigen::VectorXd::Zero(3 * n);
    const CgResult r = solve_pcg(A, P, b, 1e-10, 50, x, work);
    EXPECT_TRUE(r.converged);
    EXPECT_EQ(r.iterations, 1) << "scaled " << scaled;
    EXPECT_LT((A.to_dense() * x - b).norm(), 1e-10 * b.norm());
  }
}

}  // namespace
}  // namespace tissu
