#include "physics/membrane.h"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <random>

#include "physics/biphasic.h"
#include "physics/block_triplets.h"
#include "test_meshes.h"

namespace tissu {
namespace {

// A random irregular triangle: rest corners in (u, v) and deformed 3D positions.
struct RandomTriangle {
  TriangleRest rest;
  Vec3 x[3];
};

RandomTriangle random_triangle(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-0.05, 0.05);
  Model m;
  // Irregular but not degenerate: every angle above 15 degrees.
  auto min_angle = [](const Vec2List& p) {
    double smallest = M_PI;
    for (int k = 0; k < 3; ++k) {
      const Vec2 a = p[(k + 1) % 3] - p[k], b = p[(k + 2) % 3] - p[k];
      smallest = std::min(smallest, std::acos(a.dot(b) / (a.norm() * b.norm())));
    }
    return smallest;
  };
  do {
    m.rest_uv.clear();
    for (int k = 0; k < 3; ++k) m.rest_uv.emplace_back(u(rng), u(rng));
  } while (min_angle(m.rest_uv) < 15.0 * M_PI / 180.0);
  if ((m.rest_uv[1] - m.rest_uv[0]).x() * (m.rest_uv[2] - m.rest_uv[0]).y() -
          (m.rest_uv[1] - m.rest_uv[0]).y() * (m.rest_uv[2] - m.rest_uv[0]).x() <
      0) {
    std::swap(m.rest_uv[1], m.rest_uv[2]);
  }
  m.triangles.emplace_back(0, 1, 2);
  m.material.density = 1.0;
  precompute_rest(m);
  RandomTriangle t;
  t.rest = m.rest[0];
  for (int k = 0; k < 3; ++k) {
    // Deformed: rest shape lifted to 3D, stretched, sheared and rotated, plus noise.
    t.x[k] = Vec3(1.1 * m.rest_uv[k].x() + 0.2 * m.rest_uv[k].y(), 0.9 * m.rest_uv[k].y(),
                  0.3 * m.rest_uv[k].x()) +
             Vec3(u(rng), u(rng), u(rng)) * 0.3;
  }
  return t;
}

// A full symmetric positive-definite E (the kernel must not assume zero E_13, E_23).
Mat3 anisotropic_E() {
  Mat3 E;
  E << 900, 150, 40,  //
      150, 400, -30,  //
      40, -30, 80;
  return E;
}

// Linear (kappa = 1) and biphasic (kappa < 1) membranes.
TEST(Membrane, ForcesAreMinusEnergyGradientOnRandomTriangles) {
  std::mt19937 rng(7);
  const Mat3 E = anisotropic_E();
  for (int trial = 0; trial < 40; ++trial) {
    const double kappa = trial < 20 ? 1.0 : 0.05;
    RandomTriangle t = random_triangle(rng);
    Vec3 f[3];
    triangle_forces(t.rest, E, t.x, f, kappa);
    std::vector<double> errors;
    // m; the biphasic map's transition is a strain of 1e-3, so steps 10x smaller there.
    const double h0 = kappa < 1.0 ? 1e-6 : 1e-5;
    for (double h : {h0, h0 / 10}) {
      double max_error = 0.0, scale = 0.0;
      for (int j = 0; j < 3; ++j) {
        for (int a = 0; a < 3; ++a) {
          Vec3 xp[3] = {t.x[0], t.x[1], t.x[2]}, xm[3] = {t.x[0], t.x[1], t.x[2]};
          xp[j][a] += h;
          xm[j][a] -= h;
          const double dW = (triangle_energy(t.rest, E, xp[0], xp[1], xp[2], kappa) -
                             triangle_energy(t.rest, E, xm[0], xm[1], xm[2], kappa)) /
                            (2 * h);
          max_error = std::max(max_error, std::fabs(-dW - f[j][a]));
          scale = std::max(scale, std::fabs(f[j][a]));
        }
      }
      errors.push_back(max_error / scale);
    }
    // Central differences: the error is O(h^2), so a 10x smaller step cuts it >= 30x
    // (until round-off, about 1e-10 here).
    EXPECT_LT(errors[1], 1e-6) << "trial " << trial;
    EXPECT_TRUE(errors[1] < errors[0] / 30 || errors[1] < 1e-9)
        << "trial " << trial << ": " << errors[0] << " -> " << errors[1];
  }
}

// The biphasic membrane's energy (compression ratio below 1) on random triangles: that of
// the linear membrane where no yarn is compressed, positive elsewhere (not always less
// than the linear one: the weft-warp coupling is softened too).
TEST(Membrane, BiphasicEnergyIsLinearInTensionAndPositive) {
  std::mt19937 rng(11);
  const Mat3 E = anisotropic_E();
  int compressed = 0;
  for (int trial = 0; trial < 20; ++trial) {
    RandomTriangle t = random_triangle(rng);
    const Vec3 e = triangle_strain(t.rest, t.x[0], t.x[1], t.x[2]);
    compressed += (e[0] < 0.0 || e[1] < 0.0) ? 1 : 0;
    const double linear = triangle_energy(t.rest, E, t.x[0], t.x[1], t.x[2]);
    const double biphasic = triangle_energy(t.rest, E, t.x[0], t.x[1], t.x[2], 0.05);
    if (e[0] >= 0.0 && e[1] >= 0.0) {
      EXPECT_EQ(biphasic, linear) << "trial " << trial;
    } else {
      EXPECT_NE(biphasic, linear) << "trial " << trial;
    }
    EXPECT_GT(biphasic, 0.0) << "trial " << trial;
  }
  EXPECT_GE(compressed, 5);  // the trials do test compression
}

TEST(Membrane, RigidMotionGivesZeroForceAndEnergy) {
  Vec3List x;
  Model m = testing::grid_model(0.3, 0.2, 6, 5, 0.3, 3, &x);
  m.material = testing::test_material();
  precompute_rest(m);
  const Mat3 R = Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  for (Vec3& p : x) p = R * p + Vec3(0.4, -1.0, 2.0);
  Vec3List f(x.size(), Vec3::Zero());
  add_membrane_forces(m, x, nullptr, 0, m.num_triangles(), VertexForces::of(f));
  for (const Vec3& fi : f) EXPECT_LT(fi.norm(), 1e-10);
  EXPECT_LT(membrane_energy(m, x), 1e-20);
}

// A strip L x W (m) of an isotropic material (Yh N/m, Poisson ratio nu) with the
// compression ratio kappa, stretched by s along u and by lambda across: the force (N) on
// its end at +L/2. The other vertices must feel no force (below tolerance, N).
double strip_end_force(double s, double lambda, double kappa, double tolerance) {
  const double Yh = 1000.0, nu = 0.3, W = 0.1, L = 0.3;
  const double c = Yh / (1 - nu * nu);
  Vec3List x;
  Model m = testing::grid_model(L, W, 12, 5, 0.35, 11, &x);
  m.material.density = 0.1;
  m.material.weft = m.material.warp = c;
  m.material.coupling = nu * c;
  m.material.shear = Yh / (2 * (1 + nu));
  m.material.compression_ratio = kappa;
  precompute_rest(m);
  for (size_t i = 0; i < x.size(); ++i) {
    x[i] = Vec3(s * m.rest_uv[i].x(), lambda * m.rest_uv[i].y(), 0.0);
  }
  Vec3List f(x.size(), Vec3::Zero());
  add_membrane_forces(m, x, nullptr, 0, m.num_triangles(), VertexForces::of(f));
  double end_force = 0.0;
  for (size_t i = 0; i < x.size(); ++i) {
    if (m.rest_uv[i].x() > L / 2 - 1e-12) {
      end_force += f[i].x();
    } else if (m.rest_uv[i].x() > -L / 2 + 1e-12) {
      EXPECT_LT(f[i].norm(), tolerance) << "vertex " << i << " not at an end";
    }
  }
  return end_force;
}

// reference.md: strip of width W stretched by s along u, lateral edges free:
// F = W s (C_uu - C_uv^2 / C_vv) (s^2 - 1) / 2.  Yh = 1000 N/m, nu = 0.3, W = 0.1 m.
TEST(Membrane, UniaxialStretchMatchesClosedForm) {
  const double nu = 0.3;
  const std::pair<double, double> cases[] = {
      {1.01, 1.01505}, {1.05, 5.38125}, {1.10, 11.5500}, {1.20, 26.400}};
  for (const auto& [s, expected] : cases) {
    // Lateral contraction for zero transverse stress: e_vv = -nu e_uu.
    const double e_uu = (s * s - 1) / 2, e_vv = -nu * e_uu;
    const double end_force = strip_end_force(s, std::sqrt(1 + 2 * e_vv), 1.0, 1e-9 * expected);
    // The pulled end is pulled back by the membrane: the force on it is -F.
    EXPECT_NEAR(-end_force, expected, 1e-8 * expected) << "s = " << s;
  }
}

// The same strip compressed along u (s < 1) with the compression ratio kappa
// (biphasic.h): the weft strain counts as phi(e_uu), so the lateral strain for zero
// transverse stress is e_vv = -nu phi(e_uu) and the end force is
// F = W s c (1 - nu^2) phi'(e_uu) phi(e_uu), with phi written out here. Beyond a few
// buckling strains the force is close to kappa times the linear one.
TEST(Membrane, UniaxialCompressionMatchesTheBiphasicClosedForm) {
  const double Yh = 1000.0, nu = 0.3, W = 0.1, d = kYarnBucklingStrain;
  const double c = Yh / (1 - nu * nu);
  for (double kappa : {1.0, 0.1, 0.01}) {
    for (double s : {0.999, 0.99, 0.95}) {
      const double e_uu = (s * s - 1) / 2, k = std::sqrt(kappa);
      const double phi = k * e_uu + (1 - k) * d * (std::exp(e_uu / d) - 1);
      const double slope = k + (1 - k) * std::exp(e_uu / d);
      const double end_force = strip_end_force(s, std::sqrt(1 - 2 * nu * phi), kappa, 1e-9 * c * W);
      const double expected = W * s * c * (1 - nu * nu) * slope * phi;  // N
      const double linear = W * s * c * (1 - nu * nu) * e_uu;           // N
      EXPECT_NEAR(-end_force, expected, 1e-8 * std::fabs(expected))
          << "kappa " << kappa << ", s " << s;
      if (s == 0.95 && kappa < 1.0) {
        EXPECT_GT(-end_force / linear, kappa) << "kappa " << kappa;
        EXPECT_LT(-end_force / linear, 1.5 * kappa) << "kappa " << kappa;
      }
    }
  }
}

// Assembles the dense Jacobian of the membrane force for finite-difference checks.
Eigen::MatrixXd dense(const BlockTriplets& t, int n) { return Eigen::MatrixXd(t.to_sparse(n)); }

// The membrane Jacobian c_x df/dx + c_v df/dv of the whole mesh as triplets.
BlockTriplets membrane_jacobian(const Model& m, const Vec3List& x, bool project_psd, double cx,
                                double cv) {
  BlockTriplets out;
  TripletSink sink(cx, cv, out);
  add_membrane_jacobian(m, x, nullptr, project_psd, 0, m.num_triangles(), sink);
  return out;
}

Eigen::VectorXd forces_of(const Model& m, const Vec3List& x, const Vec3List* v) {
  Vec3List f(x.size(), Vec3::Zero());
  add_membrane_forces(m, x, v, 0, m.num_triangles(), VertexForces::of(f));
  Eigen::VectorXd out(3 * x.size());
  for (size_t i = 0; i < x.size(); ++i) out.segment<3>(3 * i) = f[i];
  return out;
}

// df/dx by central differences of the forces with step h (m).
Eigen::MatrixXd position_jacobian_by_differences(const Model& m, const Vec3List& x, double h) {
  const int n = static_cast<int>(x.size());
  Eigen::MatrixXd K_fd(3 * n, 3 * n);
  for (int c = 0; c < 3 * n; ++c) {
    Vec3List xp = x, xm = x;
    xp[c / 3][c % 3] += h;
    xm[c / 3][c % 3] -= h;
    K_fd.col(c) = (forces_of(m, xp, nullptr) - forces_of(m, xm, nullptr)) / (2 * h);
  }
  return K_fd;
}

// df/dv by central differences of the forces (exact: the damping force is linear in v).
Eigen::MatrixXd velocity_jacobian_by_differences(const Model& m, const Vec3List& x,
                                                 const Vec3List& v) {
  const int n = static_cast<int>(x.size());
  Eigen::MatrixXd D_fd(3 * n, 3 * n);
  for (int c = 0; c < 3 * n; ++c) {
    Vec3List vp = v, vm = v;
    vp[c / 3][c % 3] += 1e-4;
    vm[c / 3][c % 3] -= 1e-4;
    D_fd.col(c) = (forces_of(m, x, &vp) - forces_of(m, x, &vm)) / 2e-4;
  }
  return D_fd;
}

TEST(Membrane, JacobianMatchesFiniteDifferencesOfForces) {
  Vec3List x;
  Model m = testing::grid_model(0.1, 0.08, 3, 3, 0.3, 5, &x);
  m.material = testing::test_material();
  precompute_rest(m);
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> noise(-0.01, 0.01);
  for (Vec3& p : x) p = Vec3(1.05 * p.x(), 0.97 * p.y(), 0.0) + Vec3(noise(rng), noise(rng), noise(rng));
  const int n = static_cast<int>(x.size());
  const BlockTriplets dfdx = membrane_jacobian(m, x, /*project_psd=*/false, 1.0, 0.0);
  const Eigen::MatrixXd K = dense(dfdx, n);
  double previous = INFINITY;
  for (double h : {1e-5, 1e-6}) {
    const Eigen::MatrixXd K_fd = position_jacobian_by_differences(m, x, h);
    const double relative = (K - K_fd).norm() / K.norm();
    EXPECT_LT(relative, 1e-6) << "h " << h;
    EXPECT_LT(relative, previous);
    previous = relative;
  }
  EXPECT_LT((K - K.transpose()).norm(), 1e-9 * K.norm()) << "Jacobian must be symmetric";
}

// The biphasic membrane's Jacobians df/dx and (with damping) df/dv against finite
// differences of its forces, on a sheet stretched along u and slightly compressed along v.
TEST(Membrane, BiphasicJacobianMatchesFiniteDifferencesOfForces) {
  Vec3List x;
  Model m = testing::grid_model(0.1, 0.08, 3, 3, 0.3, 5, &x);
  m.material = testing::test_material();
  m.material.compression_ratio = 0.02;
  m.material.damping = 0.01;  // s
  precompute_rest(m);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> noise(-1.0, 1.0);
  for (Vec3& p : x) {
    p = Vec3(1.002 * p.x(), 0.9988 * p.y(), 0.0) +
        Vec3(2e-5 * noise(rng), 2e-5 * noise(rng), 5e-4 * noise(rng));
  }
  // Weft and warp strains inside the smooth transition of the slope phi' (a few buckling
  // strains), where the tangent's phi'' term matters.
  int transition = 0;
  for (int t = 0; t < m.num_triangles(); ++t) {
    const Tri& tri = m.triangles[t];
    const Vec3 e = triangle_strain(m.rest[t], x[tri[0]], x[tri[1]], x[tri[2]]);
    for (int a = 0; a < 2; ++a) transition += e[a] < 0.0 && e[a] > -3 * kYarnBucklingStrain;
  }
  EXPECT_GE(transition, m.num_triangles() / 2);
  Vec3List v(x.size());
  for (Vec3& vi : v) vi = Vec3(noise(rng), noise(rng), noise(rng)) * 0.2;  // m/s
  const int n = static_cast<int>(x.size());
  const Eigen::MatrixXd K = dense(membrane_jacobian(m, x, false, 1.0, 0.0), n);
  const Eigen::MatrixXd D = dense(membrane_jacobian(m, x, false, 0.0, 1.0), n);
  // Central differences: O(h^2), with a large third derivative (phi''' ~ 1 / d^2), so the
  // error must fall 30x or more from h to h / 10, down to 1e-6.
  std::vector<double> errors;
  for (double h : {1e-7, 1e-8}) {
    const Eigen::MatrixXd K_fd = position_jacobian_by_differences(m, x, h);
    errors.push_back((K - K_fd).norm() / K.norm());
  }
  EXPECT_LT(errors[1], 1e-6);
  EXPECT_LT(errors[1], errors[0] / 30);
  EXPECT_LT((K - K.transpose()).norm(), 1e-9 * K.norm()) << "Jacobian must be symmetric";
  const Eigen::MatrixXd D_fd = velocity_jacobian_by_differences(m, x, v);
  EXPECT_LT((D - D_fd).norm() / D.norm(), 1e-8);
  // The compressed yarns' stiffness is kappa times the linear one's: a softer Jacobian.
  m.material.compression_ratio = 1.0;
  EXPECT_LT(K.norm(), 0.9 * dense(membrane_jacobian(m, x, false, 1.0, 0.0), n).norm());
}

TEST(Membrane, ProjectedJacobianIsNegativeSemiDefiniteUnderCompression) {
  Vec3List x;
  Model m = testing::grid_model(0.1, 0.1, 3, 3, 0.3, 9, &x);
  m.material = testing::test_material();
  precompute_rest(m);
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> noise(-0.01, 0.01);
  for (Vec3& p : x) p = 0.8 * p + Vec3(noise(rng), noise(rng), noise(rng));  // compressed
  const int n = static_cast<int>(x.size());
  const BlockTriplets exact = membrane_jacobian(m, x, false, 1.0, 0.0);
  const BlockTriplets projected = membrane_jacobian(m, x, true, 1.0, 0.0);
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> e_exact(dense(exact, n));
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> e_proj(dense(projected, n));
  // Compression makes the exact -df/dx indefinite; the projected one is not.
  EXPECT_GT(e_exact.eigenvalues().maxCoeff(), 1e-6);
  EXPECT_LT(e_proj.eigenvalues().maxCoeff(), 1e-9 * e_proj.eigenvalues().cwiseAbs().maxCoeff());
}

// The projected, damped Jacobian against its definition written term by term: blocks
// -A (c_x + c_v tau) J_i E J_j^T - c_x A (r_i^T S+ r_j) I, with J_i's columns de_a/dx_i,
// S the elastic plus viscous stress and S+ its eigenvalues clamped at zero. The sheet is
// stretched along u and compressed along v, so stresses of every sign occur.
TEST(Membrane, ProjectedDampedJacobianIsItsTermByTermDefinition) {
  Vec3List x;
  Model m = testing::grid_model(0.1, 0.08, 4, 3, 0.3, 11, &x);
  m.material = testing::test_material();
  m.material.damping = 0.01;  // s
  precompute_rest(m);
  std::mt19937 rng(12);
  std::uniform_real_distribution<double> noise(-1.0, 1.0);
  for (Vec3& p : x) {
    p = Vec3(1.01 * p.x(), 0.99 * p.y(), 0.0) + 0.002 * Vec3(noise(rng), noise(rng), noise(rng));
  }
  Vec3List v(x.size());
  for (Vec3& vi : v) vi = 0.2 * Vec3(noise(rng), noise(rng), noise(rng));  // m/s
  const double cx = 0.7, cv = 0.2, tau = m.material.damping;
  const Mat3 E = m.material.stiffness();
  const int n = static_cast<int>(x.size());
  Eigen::MatrixXd expected = Eigen::MatrixXd::Zero(3 * n, 3 * n);
  int signs[3] = {0, 0, 0};  // triangles with stress eigenvalues both >= 0, mixed, both < 0
  for (int t = 0; t < m.num_triangles(); ++t) {
    const Tri& tri = m.triangles[t];
    const TriangleRest& r = m.rest[t];
    Vec3 U = Vec3::Zero(), V = Vec3::Zero(), dU = Vec3::Zero(), dV = Vec3::Zero();
    for (int j = 0; j < 3; ++j) {
      U += r.ru[j] * x[tri[j]];
      V += r.rv[j] * x[tri[j]];
      dU += r.ru[j] * v[tri[j]];
      dV += r.rv[j] * v[tri[j]];
    }
    const Vec3 strain(0.5 * (U.squaredNorm() - 1.0), 0.5 * (V.squaredNorm() - 1.0), U.dot(V));
    const Vec3 rate(U.dot(dU), V.dot(dV), U.dot(dV) + dU.dot(V));
    const Vec3 s = E * (strain + tau * rate);
    Eigen::Matrix2d S;
    S << s[0], s[2], s[2], s[1];
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(S);
    const Eigen::Vector2d lambda = eig.eigenvalues();
    ++signs[lambda[0] >= 0.0 ? 0 : (lambda[1] >= 0.0 ? 1 : 2)];
    const Eigen::Matrix2d S_plus = eig.eigenvectors() * lambda.cwiseMax(0.0).asDiagonal() *
                                   eig.eigenvectors().transpose();
    Eigen::Matrix3d J[3];
    for (int j = 0; j < 3; ++j) {
      J[j].col(0) = r.ru[j] * U;
      J[j].col(1) = r.rv[j] * V;
      J[j].col(2) = r.ru[j] * V + r.rv[j] * U;
    }
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        const Eigen::Vector2d ri(r.ru[i], r.rv[i]), rj(r.ru[j], r.rv[j]);
        const Eigen::Matrix3d block = -r.area * (cx + cv * tau) * (J[i] * E * J[j].transpose()) -
                                      cx * r.area * ri.dot(S_plus * rj) * Mat3::Identity();
        expected.block<3, 3>(3 * tri[i], 3 * tri[j]) += block;
      }
    }
  }
  EXPECT_GT(signs[0], 0);
  EXPECT_GT(signs[1], 0);
  BlockTriplets out;
  TripletSink sink(cx, cv, out);
  add_membrane_jacobian(m, x, &v, /*project_psd=*/true, 0, m.num_triangles(), sink);
  const Eigen::MatrixXd K = dense(out, n);
  EXPECT_LT((K - expected).norm(), 1e-12 * expected.norm());
}

TEST(Membrane, DampingForceAndVelocityJacobian) {
  Vec3List x;
  Model m = testing::grid_model(0.1, 0.08, 3, 2, 0.3, 6, &x);
  m.material = testing::test_material();
  m.material.damping = 0.01;  // s
  precompute_rest(m);
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> noise(-0.2, 0.2);
  Vec3List v(x.size());
  for (Vec3& vi : v) vi = Vec3(noise(rng), noise(rng), noise(rng));
  for (Vec3& p : x) p = Vec3(1.02 * p.x(), p.y(), 0.01 * p.x());
  // Rigid translation velocity: no strain rate, no damping force.
  Vec3List drift(x.size(), Vec3(0.3, -0.2, 0.1));
  EXPECT_LT((forces_of(m, x, &drift) - forces_of(m, x, nullptr)).norm(), 1e-12);
  // df/dv against finite differences (the damping force is linear in v).
  const int n = static_cast<int>(x.size());
  const BlockTriplets dfdv = membrane_jacobian(m, x, false, 0.0, 1.0);
  const Eigen::MatrixXd D = dense(dfdv, n);
  const Eigen::MatrixXd D_fd = velocity_jacobian_by_differences(m, x, v);
  EXPECT_LT((D - D_fd).norm() / D.norm(), 1e-8);
  EXPECT_GT(D.norm(), 0.0);
}

}  // namespace
}  // namespace tissu
