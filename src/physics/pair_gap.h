// The gap of a barrier pair (mesh_barrier.h, self_barrier.h): the distance between a point
// and a triangle, or two segments, past a thickness, as a function of the cloth vertices
// that take part, with its gradient and its second derivative (1/m).
// The distance is r = |sum_k w_k P_k| at the closest points, whose weights w are affine in
// the closest points' free parameters alpha (barycentric coordinates strictly inside their
// feature: two on a face, one on an edge, none at a corner). With q = sum_k w_k P_k (3),
// J_j = d q / d alpha_j and C_j = (d w / d alpha_j) (x) q + w (x) J_j (3 count):
//   d r / d x = w (x) n,
//   d^2 r / d x^2 = [(w w^T) (x) (I - n n^T) - C (J^T J)^+ C^T] / r,
// the second term the closest points sliding along their feature (the envelope of
// min over alpha of |q|^2 / 2). Tested in tests/physics/pair_gap_test.cpp.
#pragma once

#include <Eigen/Core>
#include <array>

#include "collision/primitive_distance.h"
#include "core/types.h"

namespace tissu {

// One pair's gap at given cloth positions: the cloth vertices it moves and their weights,
// so that d gap / d x_k = weights[k] normal (world, unit). Against an obstacle's feature the
// normal points from the feature toward the cloth and the weights are those of the cloth's
// closest point; between two pieces of cloth (self_barrier.h) the normal points from the
// second piece toward the first and the second's weights are negative.
struct PairGap {
  double d = 0.0;  // m, past the thickness
  Vec3 normal = Vec3::UnitZ();
  int vertices[4] = {-1, -1, -1, -1};
  double weights[4] = {0.0, 0.0, 0.0, 0.0};
  int count = 0;  // 3 for a cloth triangle, 2 for a cloth edge, 4 for two pieces of cloth
  // Vertices [0, split) and [split, count) belong to two pieces of cloth whose vertices
  // share no triangle: the step's matrix has no blocks between them (count: one piece).
  int split = 0;
  // For the second derivative, filled by the self pairs (a mesh feature pair's matrix
  // takes the Gauss-Newton part only, mesh_barrier.h): r, the distance between the closest
  // points (m), and their free parameters: d q / d alpha_j (tangents, world, m) and
  // d w_k / d alpha_j over the count vertices (weight_slopes).
  double distance = 0.0;
  int params = 0;
  Vec3 tangents[2] = {Vec3::Zero(), Vec3::Zero()};
  double weight_slopes[2][4] = {{0.0, 0.0, 0.0, 0.0}, {0.0, 0.0, 0.0, 0.0}};
  // Edge-edge pairs between pieces of cloth: the edges p1 - p0 and p3 - p2 (m) and the
  // mollifier's threshold eps_x (m^4, cross_limit_at_rest); 0 for other pairs.
  Vec3 edges[2] = {Vec3::Zero(), Vec3::Zero()};
  double cross_limit = 0.0;

  // The free parameters of a closest point on segment (p0, p1) at s, whose weights
  // (1 - s, s) times sign sit at weights[first], weights[first + 1].
  void add_segment_params(double s, int first, double sign, const Vec3& p0, const Vec3& p1);
  // The same for a closest point on feature f of triangle (a, b, c), weights at
  // weights[first .. first + 2].
  void add_triangle_params(TriangleFeature f, int first, double sign, const Vec3& a,
                           const Vec3& b, const Vec3& c);
};

// Over the 3 count coordinates of the pair's vertices (the rest zero).
using PairMatrix = Eigen::Matrix<double, 12, 12>;
using PairVector = Eigen::Matrix<double, 12, 1>;

// The second derivative of a function of the gap, f(gap), in the pair's vertices:
//   f'' grad grad^T + f' Hess gap,   slope f' and curvature f'' at g.d
// (the gap's own, 1/m, for slope 1 and curvature 0; a barrier's, N/m, for b' and b'',
// indefinite where the closest points turn or slide, since b' < 0),
// with the rows and columns of vertices marked in `fixed` (may be null) zero; exact, or
// (psd) projected to positive semi-definite (negative eigenvalues set to zero). Its range
// lies in the span of w (x) n, w (x) t1, w (x) t2 (t1, t2 across n) and C's columns, at
// most five vectors, where the projection is taken.
PairMatrix gap_function_hessian(const PairGap& g, double slope, double curvature, bool psd,
                                const bool* fixed = nullptr);

// IPC's mollifier of an edge-edge pair (Li et al. 2020): with c = |e0 x e1|^2 (m^4),
//   m(c) = (c / eps_x) (2 - c / eps_x) below eps_x, 1 from eps_x on.
// Where two edges turn parallel their closest points jump along them and the gap's
// gradient with them; the pair's barrier m(c) b(gap) goes smoothly to zero there instead
// (the point-triangle pairs of the same edges' triangles hold them apart). 1 for a pair
// without a threshold.
double edge_mollifier(const PairGap& g);
// Whether g's barrier is mollified: an edge-edge pair with c < eps_x.
bool is_mollified(const PairGap& g);
// eps_x of the edges ids[0]-ids[1] and ids[2]-ids[3] of a cloth with rest coordinates
// rest_uv (m): a share of the product of their squared rest lengths (m^4), which puts
// edges within about 0.18 degrees of parallel below it.
double cross_limit_at_rest(const Vec2List& rest_uv, const std::array<int, 4>& ids);

// The gradient and second derivative of m(c) f(gap) in the pair's vertices, for f, its
// slope f' and curvature f'' at g.d (a barrier's J, N and N/m): exact, or (psd) projected
// to positive semi-definite, with the rows and columns of vertices marked in `fixed` (may
// be null) zero.
PairVector mollified_gradient(const PairGap& g, double value, double slope);
PairMatrix mollified_hessian(const PairGap& g, double value, double slope, double curvature,
                             bool psd, const bool* fixed = nullptr);

}  // namespace tissu
