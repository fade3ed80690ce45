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

namespace {

// The mollifier's threshold eps_x as a share of the product of the edges' squared rest
// lengths. IPC's 1e-3 (1.8 degrees) made folding runs take up to 35% more Newton
// iterations, while this share keeps its effect on layers laid parallel (docs/implicit.md).
constexpr double kMollifierShare = 1e-5;

// c = |e0 x e1|^2 (m^4) with its gradient and second derivative in the four vertices,
// where e0 = p1 - p0 and e1 = p3 - p2.
struct CrossSquared {
  double c = 0.0;
  PairVector gradient;
  PairMatrix hessian;
};

CrossSquared cross_squared(const PairGap& g) {
  const Vec3& a = g.edges[0];
  const Vec3& b = g.edges[1];
  const double aa = a.squaredNorm(), bb = b.squaredNorm(), ab = a.dot(b);
  const Mat3 identity = Mat3::Identity();
  // In (e0, e1): c = |a|^2 |b|^2 - (a . b)^2.
  Eigen::Matrix<double, 6, 1> g6;
  g6 << 2.0 * (bb * a - ab * b), 2.0 * (aa * b - ab * a);
  Eigen::Matrix<double, 6, 6> h6;
  h6.topLeftCorner<3, 3>() = 2.0 * (bb * identity - b * b.transpose());
  h6.bottomRightCorner<3, 3>() = 2.0 * (aa * identity - a * a.transpose());
  h6.topRightCorner<3, 3>() =
      4.0 * a * b.transpose() - 2.0 * b * a.transpose() - 2.0 * ab * identity;
  h6.bottomLeftCorner<3, 3>() = h6.topRightCorner<3, 3>().transpose();
  // (e0, e1) = S p with S = [[-I, I, 0, 0], [0, 0, -I, I]].
  Eigen::Matrix<double, 6, 12> select = Eigen::Matrix<double, 6, 12>::Zero();
  select.block<3, 3>(0, 0) = -identity;
  select.block<3, 3>(0, 3) = identity;
  select.block<3, 3>(3, 6) = -identity;
  select.block<3, 3>(3, 9) = identity;
  CrossSquared out;
  out.c = a.cross(b).squaredNorm();
  out.gradient = select.transpose() * g6;
  out.hessian = select.transpose() * h6 * select;
  return out;
}

// m(c) and its first two derivatives in c (1, m^-4, m^-8) below eps_x.
struct MollifierValues {
  double m, dm, ddm;
};

MollifierValues mollifier_at(double c, double eps) {
  const double r = c / eps;
  return {r * (2.0 - r), (2.0 - 2.0 * r) / eps, -2.0 / (eps * eps)};
}

PairVector gap_gradient(const PairGap& g) {
  PairVector out = PairVector::Zero();
  for (int k = 0; k < g.count; ++k) out.segment<3>(3 * k) = g.weights[k] * g.normal;
  return out;
}

}  // namespace

double edge_mollifier(const PairGap& g) {
  if (g.cross_limit <= 0.0) return 1.0;
  const double c = g.edges[0].cross(g.edges[1]).squaredNorm();  // m^4
  return c < g.cross_limit ? mollifier_at(c, g.cross_limit).m : 1.0;
}

bool is_mollified(const PairGap& g) {
  return g.cross_limit > 0.0 && g.edges[0].cross(g.edges[1]).squaredNorm() < g.cross_limit;
}

double cross_limit_at_rest(const Vec2List& rest_uv, const std::array<int, 4>& ids) {
  return kMollifierShare * (rest_uv[ids[1]] - rest_uv[ids[0]]).squaredNorm() *
         (rest_uv[ids[3]] - rest_uv[ids[2]]).squaredNorm();
}

PairVector mollified_gradient(const PairGap& g, double value, double slope) {
  if (!is_mollified(g)) return slope * gap_gradient(g);
  const CrossSquared c = cross_squared(g);
  const MollifierValues m = mollifier_at(c.c, g.cross_limit);
  return m.m * slope * gap_gradient(g) + value * m.dm * c.gradient;
}

PairMatrix mollified_hessian(const PairGap& g, double value, double slope, double curvature,
                             bool psd, const bool* fixed) {
  if (!is_mollified(g)) return gap_function_hessian(g, slope, curvature, psd, fixed);
  const CrossSquared c = cross_squared(g);
  const MollifierValues m = mollifier_at(c.c, g.cross_limit);
  const PairVector grad_m = m.dm * c.gradient;
  const PairVector grad_gap = gap_gradient(g);
  // m f'' grad grad^T + m f' Hess gap + f Hess m + f' (grad m grad^T + grad grad m^T).
  PairMatrix h = m.m * gap_function_hessian(g, slope, curvature, false) +
                 value * (m.ddm * c.gradient * c.gradient.transpose() + m.dm * c.hessian) +
                 slope * (grad_m * grad_gap.transpose() + grad_gap * grad_m.transpose());
  const auto zero_fixed = [&](PairMatrix& matrix) {
    for (int k = 0; fixed && k < g.count; ++k) {
      if (!fixed[k]) continue;
      matrix.middleRows<3>(3 * k).setZero();
      matrix.middleCols<3>(3 * k).setZero();
    }
  };
  zero_fixed(h);
  if (!psd) return h;
  const Eigen::SelfAdjointEigenSolver<PairMatrix> eig(h);
  PairMatrix projected = eig.eigenvectors() * eig.eigenvalues().cwiseMax(0.0).asDiagonal() *
                         eig.eigenvectors().transpose();
  zero_fixed(projected);  // rounding of the decomposition
  return projected;
}

}  // namespace tissu
