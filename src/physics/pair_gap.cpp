#include "physics/pair_gap.h"

#include <Eigen/Eigenvalues>
#include <Eigen/QR>

namespace tissu {

void PairGap::add_segment_params(double s, int first, double sign, const Vec3& p0,
                                 const Vec3& p1) {
  if (!(s > 0.0 && s < 1.0)) return;
  const int j = params++;
  tangents[j] = sign * (p1 - p0);
  weight_slopes[j][first] = -sign;
  weight_slopes[j][first + 1] = sign;
}

void PairGap::add_triangle_params(TriangleFeature f, int first, double sign, const Vec3& a,
                                  const Vec3& b, const Vec3& c) {
  const Vec3* corner[3] = {&a, &b, &c};
  // A parameter moving the closest point from corner `from` toward corner `to`.
  const auto add = [&](int from, int to) {
    const int j = params++;
    tangents[j] = sign * (*corner[to] - *corner[from]);
    weight_slopes[j][first + from] = -sign;
    weight_slopes[j][first + to] = sign;
  };
  switch (f) {
    case TriangleFeature::Face:
      add(0, 1);
      add(0, 2);
      break;
    case TriangleFeature::EdgeAB: add(0, 1); break;
    case TriangleFeature::EdgeBC: add(1, 2); break;
    case TriangleFeature::EdgeCA: add(0, 2); break;
    default: break;  // a corner: no free parameter
  }
}

namespace {

// Below this fraction of the largest, an eigenvalue of J^T J counts as zero: parameters
// whose motions are parallel (nearly parallel edges) slide the closest points freely and
// their pseudo-inverse drops that direction.
constexpr double kParallelFraction = 1e-8;

// (J^T J)^+ over the closest points' free parameters (2 x 2, zero beyond params).
Eigen::Matrix2d gram_inverse(const PairGap& g) {
  Eigen::Matrix2d inverse = Eigen::Matrix2d::Zero();
  if (g.params == 1) {
    const double gram = g.tangents[0].squaredNorm();
    if (gram > 0.0) inverse(0, 0) = 1.0 / gram;
  } else if (g.params == 2) {
    Eigen::Matrix2d gram;
    for (int i = 0; i < 2; ++i) {
      for (int j = 0; j < 2; ++j) gram(i, j) = g.tangents[i].dot(g.tangents[j]);
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(gram);
    const double largest = eig.eigenvalues()[1];
    for (int i = 0; i < 2; ++i) {
      const double e = eig.eigenvalues()[i];
      if (e > kParallelFraction * largest) {
        inverse += eig.eigenvectors().col(i) * eig.eigenvectors().col(i).transpose() / e;
      }
    }
  }
  return inverse;
}

// The vectors the gap's second derivative is made of, as columns: w (x) n, w (x) t1,
// w (x) t2, C_1, C_2 (zero beyond params).
using PairBasis = Eigen::Matrix<double, 12, 5>;
PairBasis pair_basis(const PairGap& g) {
  PairBasis v = PairBasis::Zero();
  const Vec3 t1 = g.normal.unitOrthogonal();
  const Vec3 t2 = g.normal.cross(t1);
  const Vec3 q = g.distance * g.normal;
  for (int k = 0; k < g.count; ++k) {
    v.block<3, 1>(3 * k, 0) = g.weights[k] * g.normal;
    v.block<3, 1>(3 * k, 1) = g.weights[k] * t1;
    v.block<3, 1>(3 * k, 2) = g.weights[k] * t2;
    for (int j = 0; j < g.params; ++j) {
      v.block<3, 1>(3 * k, 3 + j) = g.weight_slopes[j][k] * q + g.weights[k] * g.tangents[j];
    }
  }
  return v;
}

// The coefficients K of f'' grad grad^T + f' Hess gap = V K V^T in that basis.
Eigen::Matrix<double, 5, 5> pair_coefficients(const PairGap& g, double slope, double curvature) {
  Eigen::Matrix<double, 5, 5> k = Eigen::Matrix<double, 5, 5>::Zero();
  k(0, 0) = curvature;
  if (g.distance > 0.0) {
    const double across = slope / g.distance;  // (w w^T) (x) (I - n n^T) = V_1 V_1^T + V_2 V_2^T
    k(1, 1) = k(2, 2) = across;
    k.bottomRightCorner<2, 2>() = -across * gram_inverse(g);
  }
  return k;
}

}  // namespace

PairMatrix gap_function_hessian(const PairGap& g, double slope, double curvature, bool psd,
                                const bool* fixed) {
  PairBasis v = pair_basis(g);
  if (fixed) {
    for (int k = 0; k < g.count; ++k) {
      if (fixed[k]) v.middleRows<3>(3 * k).setZero();
    }
  }
  const Eigen::Matrix<double, 5, 5> k = pair_coefficients(g, slope, curvature);
  if (!psd) return v * k * v.transpose();
  // V = Q R: the matrix is Q (R K R^T) Q^T, projected in the five dimensions of Q.
  const Eigen::HouseholderQR<PairBasis> qr(v);
  const Eigen::Matrix<double, 12, 5> q = qr.householderQ() * Eigen::Matrix<double, 12, 5>::Identity();
  const Eigen::Matrix<double, 5, 5> r = qr.matrixQR().topRows<5>().triangularView<Eigen::Upper>();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 5, 5>> eig(r * k * r.transpose());
  const Eigen::Matrix<double, 12, 5> e = q * eig.eigenvectors();
  return e * eig.eigenvalues().cwiseMax(0.0).asDiagonal() * e.transpose();
}

}  // namespace tissu
