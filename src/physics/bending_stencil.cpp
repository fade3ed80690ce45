// The bending term's constant per-triangle stencils; see bending_stencil.h and
// docs/bending.md.
#include "physics/bending_stencil.h"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <numeric>
#include <string>
#include <utility>

#include "core/error.h"

namespace tissu {

namespace {


// An interior triangle keeps its three hinge apices as extra stencil points unless they
// nearly lie on a conic through its corners: sigma_min/sigma_max of the bubble matrix M
// below kMinConditioning, or weights |w|_F * l^2 above kMaxAmplification (l^2: mean squared
// edge length of the triangle). Measured |w|_F * l^2 with hinge apices: 3.3-3.9 on an
// equilateral lattice, 5.3 on right-triangle grids, at most 7.3-9.5 on the project's
// irregular (Delaunay) rectangles and disks, median 4.9 and 99th percentile 9.6 on
// lattices whose interior points are jittered by 0.3 spacings.
constexpr double kMinConditioning = 0.05;
constexpr double kMaxAmplification = 10.0;
// Candidate extra vertices considered for boundary / fallback / least-squares stencils
// (nearest first).
constexpr int kMaxCandidates = 12;
constexpr int kMaxFitNodes = 3 + kMaxCandidates;

inline double cross2(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

// Mean squared edge length of triangle p, m^2.
double mean_squared_edge(const Vec2 p[3]) {
  return ((p[1] - p[0]).squaredNorm() + (p[2] - p[1]).squaredNorm() +
          (p[0] - p[2]).squaredNorm()) /
         3.0;
}

// Gradients of the barycentric coordinates of triangle p, 1/m (the paper's r_u, r_v of
// eq. 2); d is twice its signed area.
void barycentric_gradients(const Vec2 p[3], double d, Vec2 g[3]) {
  for (int i = 0; i < 3; ++i) {
    const Vec2& a = p[(i + 1) % 3];
    const Vec2& b = p[(i + 2) % 3];
    g[i] = Vec2(a.y() - b.y(), b.x() - a.x()) / d;
  }
}

// Second-derivative weights of one triangle for a given set of extra points.
struct Fit {
  int count = 0;                                // 3 + number of extra points
  double w[3][kMaxFitNodes] = {};  // [uu, vv, uv][node], 1/m^2
  double g[2][kMaxFitNodes] = {};  // [u, v][node]: the patch's gradient at the centroid
  double conditioning = 0.0;   // sigma_min / sigma_max of M (0 with fewer than 3 points)
  double amplification = 0.0;  // |w|_F * l^2, dimensionless
  double truncation = 0.0;     // sum |w| |q - centroid|^3 / l: bound on the O(h) error
};

// Quadratic patch on triangle p (rest coordinates) through the extra points q (at most 3):
// f = (affine interpolant on the triangle) + sum_k beta_k b_k, with the edge bubbles
// b_k = phi_{k+1} phi_{k+2} (phi = barycentric coordinates), which span the quadratics
// vanishing at the corners. beta solves M beta = r, M_jk = b_k(q_j), r_j = residual of the
// affine interpolant at q_j (exactly when M is 3x3 invertible, else minimum-norm).
// The Hessian of f, sum_k beta_k Hess(b_k), is then a linear combination of the node
// values that is exact whenever f is quadratic (M of rank 3) and is zero whenever the node
// values are affine (r = 0).
Fit fit_hessian(const Vec2 p[3], const std::vector<Vec2>& q) {
  const double d = cross2(p[1] - p[0], p[2] - p[0]);  // twice the signed area, m^2
  const double l2 = mean_squared_edge(p);
  auto phi = [&](int i, const Vec2& w) {
    return cross2(p[(i + 1) % 3] - w, p[(i + 2) % 3] - w) / d;
  };
  Vec2 g[3];  // barycentric gradients, 1/m
  barycentric_gradients(p, d, g);
  // Constant Hessians (uu, vv, uv) of the bubbles, 1/m^2.
  double hb[3][3];
  for (int k = 0; k < 3; ++k) {
    const Vec2& a = g[(k + 1) % 3];
    const Vec2& b = g[(k + 2) % 3];
    hb[k][0] = 2.0 * a.x() * b.x();
    hb[k][1] = 2.0 * a.y() * b.y();
    hb[k][2] = a.x() * b.y() + a.y() * b.x();
  }

  const int m = static_cast<int>(q.size());
  Fit fit;
  fit.count = 3 + m;
  for (int i = 0; i < 3; ++i) {
    fit.g[0][i] = g[i].x();
    fit.g[1][i] = g[i].y();
  }
  if (m == 0) return fit;
  // At most 3 x 3: fixed-capacity storage.
  using SmallMatrix = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor, 3, 3>;
  SmallMatrix M(m, 3), Phi(m, 3);
  for (int j = 0; j < m; ++j) {
    for (int i = 0; i < 3; ++i) Phi(j, i) = phi(i, q[j]);
    for (int k = 0; k < 3; ++k) M(j, k) = Phi(j, (k + 1) % 3) * Phi(j, (k + 2) % 3);
  }
  // Pseudo-inverse P = V S^+ U^T of M (3 x m).
  Eigen::JacobiSVD<SmallMatrix> svd(M, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const auto& s = svd.singularValues();
  Eigen::Vector3d s_inv = Eigen::Vector3d::Zero();
  for (int i = 0; i < s.size(); ++i) {
    if (s[i] > 1e-12 * s[0]) s_inv[i] = 1.0 / s[i];
  }
  Eigen::Matrix<double, 3, Eigen::Dynamic, 0, 3, 3> P(3, m);
  for (int k = 0; k < 3; ++k) {
    for (int j = 0; j < m; ++j) {
      double sum = 0.0;
      for (int i = 0; i < s.size(); ++i) {
        sum += svd.matrixV()(k, i) * s_inv[i] * svd.matrixU()(j, i);
      }
      P(k, j) = sum;
    }
  }
  fit.conditioning = m < 3 ? 0.0 : s[s.size() - 1] / s[0];

  // Weights: extra point j gets c_j = sum_k Hess(b_k) P_kj, corner i gets
  // -sum_j c_j phi_i(q_j) (the affine interpolant subtracted from r).
  const Vec2 centroid = (p[0] + p[1] + p[2]) / 3.0;
  double r3[kMaxFitNodes];
  for (int n = 0; n < fit.count; ++n) {
    r3[n] = std::pow(((n < 3 ? p[n] : q[n - 3]) - centroid).norm(), 3);
  }
  // Gradients of the bubbles at the centroid (phi = 1/3 there), 1/m.
  for (int c = 0; c < 2; ++c) {
    for (int j = 0; j < m; ++j) {
      double w = 0.0;
      for (int k = 0; k < 3; ++k) w += (g[(k + 1) % 3][c] + g[(k + 2) % 3][c]) / 3.0 * P(k, j);
      fit.g[c][3 + j] = w;
      for (int i = 0; i < 3; ++i) fit.g[c][i] -= w * Phi(j, i);
    }
  }
  double sum_sq = 0.0, sum_r3 = 0.0;
  for (int c = 0; c < 3; ++c) {
    for (int j = 0; j < m; ++j) {
      double w = 0.0;
      for (int k = 0; k < 3; ++k) w += hb[k][c] * P(k, j);
      fit.w[c][3 + j] = w;
      for (int i = 0; i < 3; ++i) fit.w[c][i] -= w * Phi(j, i);
    }
    for (int n = 0; n < fit.count; ++n) {
      sum_sq += fit.w[c][n] * fit.w[c][n];
      sum_r3 += std::abs(fit.w[c][n]) * r3[n];
    }
  }
  fit.amplification = l2 * std::sqrt(sum_sq);
  fit.truncation = sum_r3 / std::sqrt(l2);
  return fit;
}

// Least-squares quadratic through the triangle's corners and the points q (at least 3):
// used for needle and cap triangles, where every 6-point patch that interpolates the
// triangle's own corners has large weights (the slope across the triangle is measured
// over its tiny height). Still exact for quadratic fields and zero on affine ones.
Fit fit_least_squares(const Vec2 p[3], const std::vector<Vec2>& q) {
  const int n = 3 + static_cast<int>(q.size());
  const double l2 = mean_squared_edge(p);
  const double ell = std::sqrt(l2);
  const Vec2 centroid = (p[0] + p[1] + p[2]) / 3.0;
  // Monomials 1, x, y, x^2/2, y^2/2, xy in coordinates scaled by ell.
  Eigen::Matrix<double, Eigen::Dynamic, 6, Eigen::RowMajor, kMaxFitNodes, 6> A(n, 6);
  for (int j = 0; j < n; ++j) {
    const Vec2 z = ((j < 3 ? p[j] : q[j - 3]) - centroid) / ell;
    A.row(j) << 1.0, z.x(), z.y(), 0.5 * z.x() * z.x(), 0.5 * z.y() * z.y(), z.x() * z.y();
  }
  const Eigen::Matrix<double, 6, 6> N = A.transpose() * A;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> eig(N);
  Fit fit;
  fit.count = n;
  const double lo = eig.eigenvalues()[0], hi = eig.eigenvalues()[5];
  fit.conditioning = lo > 0.0 ? std::sqrt(lo / hi) : 0.0;
  if (!(fit.conditioning > 1e-8)) return fit;
  // Rows 3..5 of (A^T A)^-1 A^T give the scaled second derivatives.
  const Eigen::Matrix<double, 6, 6> N_inv = eig.eigenvectors() *
                                            eig.eigenvalues().cwiseInverse().asDiagonal() *
                                            eig.eigenvectors().transpose();
  double sum_sq = 0.0, sum_r3 = 0.0;
  for (int j = 0; j < n; ++j) {
    const double r3 = std::pow(((j < 3 ? p[j] : q[j - 3]) - centroid).norm(), 3);
    for (int c = 0; c < 2; ++c) fit.g[c][j] = N_inv.row(1 + c).dot(A.row(j)) / ell;
    for (int c = 0; c < 3; ++c) {
      fit.w[c][j] = N_inv.row(3 + c).dot(A.row(j)) / l2;
      sum_sq += fit.w[c][j] * fit.w[c][j];
      sum_r3 += std::abs(fit.w[c][j]) * r3;
    }
  }
  fit.amplification = l2 * std::sqrt(sum_sq);
  fit.truncation = sum_r3 / ell;
  return fit;
}

bool well_posed(const Fit& fit) {
  return fit.conditioning >= kMinConditioning && fit.amplification <= kMaxAmplification;
}

struct MeshAdjacency {
  std::vector<std::vector<int>> vertex_triangles;  // (V) incident triangles
  std::map<std::pair<int, int>, std::vector<int>> edge_triangles;
};

MeshAdjacency build_adjacency(const TriList& triangles, int num_vertices) {
  MeshAdjacency adj;
  adj.vertex_triangles.resize(num_vertices);
  for (int t = 0; t < static_cast<int>(triangles.size()); ++t) {
    for (int i = 0; i < 3; ++i) {
      const int a = triangles[t][i], b = triangles[t][(i + 1) % 3];
      adj.vertex_triangles[a].push_back(t);
      adj.edge_triangles[{std::min(a, b), std::max(a, b)}].push_back(t);
    }
  }
  return adj;
}

// The hinge across edge k (opposite corner k) of triangle t: the neighbouring triangle
// and its apex, or {-1, -1} when the edge is not shared by exactly two triangles
// (boundary or non-manifold edge).
std::pair<int, int> hinge(const TriList& triangles, const MeshAdjacency& adj, int t, int k) {
  const int a = triangles[t][(k + 1) % 3], b = triangles[t][(k + 2) % 3];
  const auto it = adj.edge_triangles.find({std::min(a, b), std::max(a, b)});
  if (it == adj.edge_triangles.end() || it->second.size() != 2) return {-1, -1};
  const int other = it->second[0] == t ? it->second[1] : it->second[0];
  for (int i = 0; i < 3; ++i) {
    const int v = triangles[other][i];
    if (v != a && v != b) return {other, v};
  }
  return {-1, -1};
}

// Distinct apices of t's hinges (at most 3).
std::vector<int> hinge_apices(const TriList& triangles, const MeshAdjacency& adj, int t) {
  std::vector<int> apices;
  for (int k = 0; k < 3; ++k) {
    const int apex = hinge(triangles, adj, t, k).second;
    if (apex >= 0 && std::find(apices.begin(), apices.end(), apex) == apices.end()) {
      apices.push_back(apex);
    }
  }
  return apices;
}

// Nearby vertices (not corners of t), nearest to the triangle's centroid first: the
// vertices of triangles touching t's corners, grown ring by ring until there are enough.
std::vector<int> candidate_vertices(const TriList& triangles, const Vec2List& uv,
                                    const MeshAdjacency& adj, int t) {
  const Tri& tri = triangles[t];
  std::vector<int> seen(tri.data(), tri.data() + 3);
  std::vector<int> frontier = seen;
  std::vector<int> found;
  for (int ring = 0; ring < 4 && static_cast<int>(found.size()) < kMaxCandidates; ++ring) {
    std::vector<int> next;
    for (int v : frontier) {
      for (int nt : adj.vertex_triangles[v]) {
        for (int i = 0; i < 3; ++i) {
          const int w = triangles[nt][i];
          if (std::find(seen.begin(), seen.end(), w) != seen.end()) continue;
          seen.push_back(w);
          next.push_back(w);
          found.push_back(w);
        }
      }
    }
    if (next.empty()) break;
    frontier = std::move(next);
  }
  const Vec2 c = (uv[tri[0]] + uv[tri[1]] + uv[tri[2]]) / 3.0;
  std::stable_sort(found.begin(), found.end(), [&](int a, int b) {
    return (uv[a] - c).squaredNorm() < (uv[b] - c).squaredNorm();
  });
  if (static_cast<int>(found.size()) > kMaxCandidates) found.resize(kMaxCandidates);
  return found;
}

std::vector<Vec2> positions(const Vec2List& uv, const std::vector<int>& ids) {
  std::vector<Vec2> q;
  for (int id : ids) q.push_back(uv[id]);
  return q;
}

// Best extra points for a triangle whose hinge apices do not suffice: all `required`
// vertices plus nearby ones, at most 3 in all, containing at least one of `apices` when
// `need_apex`. Sets that determine the quadratic come first; among them, the one with
// the smallest truncation-error bound (sum |w| r^3) wins.
std::vector<int> search_extras(const TriList& triangles, const Vec2List& uv,
                               const MeshAdjacency& adj, int t, const Vec2 p[3],
                               const std::vector<int>& required, const std::vector<int>& apices,
                               bool need_apex) {
  std::vector<int> pool;
  for (int v : candidate_vertices(triangles, uv, adj, t)) {
    if (std::find(required.begin(), required.end(), v) == required.end()) pool.push_back(v);
  }
  const int need =
      std::min<int>(3 - static_cast<int>(required.size()), static_cast<int>(pool.size()));
  std::vector<int> best = required;
  double best_cost = std::numeric_limits<double>::infinity();
  std::vector<int> pick(need);
  std::iota(pick.begin(), pick.end(), 0);
  // Lexicographic enumeration of the combinations pick[0] < pick[1] < ... of the pool.
  while (true) {
    std::vector<int> ids = required;
    for (int i = 0; i < need; ++i) ids.push_back(pool[pick[i]]);
    const bool has_apex = std::any_of(ids.begin(), ids.end(), [&](int v) {
      return std::find(apices.begin(), apices.end(), v) != apices.end();
    });
    if (has_apex || !need_apex) {
      const Fit fit = fit_hessian(p, positions(uv, ids));
      const double cost = fit.conditioning >= kMinConditioning
                              ? fit.truncation
                              : 1e100 * (1.0 + fit.truncation) / (fit.conditioning + 1e-100);
      if (cost < best_cost) {
        best_cost = cost;
        best = ids;
      }
    }
    int i = need - 1;
    while (i >= 0 && pick[i] == static_cast<int>(pool.size()) - need + i) --i;
    if (i < 0) break;
    ++pick[i];
    for (int k = i + 1; k < need; ++k) pick[k] = pick[k - 1] + 1;
  }
  return best;
}

// Union-find over triangles.
struct DisjointSets {
  std::vector<int> parent;
  explicit DisjointSets(int n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  int find(int i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  }
  void unite(int a, int b) { parent[find(a)] = find(b); }
  int count() {
    int n = 0;
    for (int i = 0; i < static_cast<int>(parent.size()); ++i) n += find(i) == i ? 1 : 0;
    return n;
  }
};

// Groups of triangles tied together by their stencils: an interpolating stencil that
// contains a neighbouring triangle ties the two (on a zero-energy configuration both
// patches are affine and they agree on the shared triangle).
DisjointSets stencil_groups(const TriList& triangles, const MeshAdjacency& adj,
                            const std::vector<std::vector<int>>& extras,
                            const std::vector<uint8_t>& least_squares) {
  DisjointSets sets(static_cast<int>(triangles.size()));
  for (int t = 0; t < static_cast<int>(triangles.size()); ++t) {
    // A least-squares patch can have zero second derivatives without being affine.
    if (least_squares[t]) continue;
    for (int k = 0; k < 3; ++k) {
      const auto [other, apex] = hinge(triangles, adj, t, k);
      if (other < 0) continue;
      if (std::find(extras[t].begin(), extras[t].end(), apex) != extras[t].end()) {
        sets.unite(t, other);
      }
    }
  }
  return sets;
}

// The largest group of tied triangles of each piece of mesh (triangles connected through
// edges): main[root] = 1 for the roots of those groups.
std::vector<uint8_t> main_groups(const TriList& triangles, const MeshAdjacency& adj,
                                 DisjointSets& groups) {
  const int T = static_cast<int>(triangles.size());
  DisjointSets pieces(T);
  for (const auto& [edge, tris] : adj.edge_triangles) {
    for (size_t i = 1; i < tris.size(); ++i) pieces.unite(tris[0], tris[i]);
  }
  std::vector<int> group_size(T, 0), main_group(T, -1);
  for (int t = 0; t < T; ++t) ++group_size[groups.find(t)];
  for (int t = 0; t < T; ++t) {
    const int g = groups.find(t), piece = pieces.find(t);
    if (main_group[piece] < 0 || group_size[g] > group_size[main_group[piece]]) {
      main_group[piece] = g;
    }
  }
  std::vector<uint8_t> main(T, 0);
  for (int t = 0; t < T; ++t) {
    if (main_group[t] >= 0) main[main_group[t]] = 1;
  }
  return main;
}

// Vertices that are not a corner of a triangle of their piece's main group.
std::vector<uint8_t> untied_vertices(const TriList& triangles, DisjointSets& groups,
                                     const std::vector<uint8_t>& main, int num_vertices) {
  std::vector<uint8_t> untied(num_vertices, 0);
  for (const Tri& tri : triangles) {
    for (int i = 0; i < 3; ++i) untied[tri[i]] = 1;
  }
  for (int t = 0; t < static_cast<int>(triangles.size()); ++t) {
    if (!main[groups.find(t)]) continue;
    for (int i = 0; i < 3; ++i) untied[triangles[t][i]] = 0;
  }
  return untied;
}

// Whether the kernel of Q is (numerically) exactly the affine maps of each piece of mesh,
// given the groups of tied triangles. Each group follows one affine map a_g (3 numbers per
// coordinate); a zero-energy configuration must also satisfy: a vertex shared by two
// groups has the same position under both maps, and every stencil whose nodes lie in
// several groups has zero second derivatives. Fixing a_g = 0 for the main group of each
// piece (the affine map common to all), the kernel is exactly affine when these linear
// constraints then force every other a_g to 0. The constraints couple only nearby
// groups: each cluster of coupled groups is checked alone (a rank test), and a cluster of
// more than kMaxClusterGroups groups counts as "not proven".
constexpr int kMaxClusterGroups = 300;
bool kernel_is_affine(const TriList& triangles, const Vec2List& uv, const MeshAdjacency& adj,
                      DisjointSets& groups, const std::vector<std::vector<int>>& extras,
                      const std::vector<Fit>& fits) {
  const int T = static_cast<int>(triangles.size());
  const int V = static_cast<int>(uv.size());
  const std::vector<uint8_t> main = main_groups(triangles, adj, groups);
  bool all_main = true;
  for (int t = 0; t < T; ++t) all_main = all_main && main[groups.find(t)];
  if (all_main) return true;

  // Affine basis (1, u, v) in coordinates centred and scaled to the mesh.
  Vec2 lo = uv[0], hi = uv[0];
  for (const Vec2& p : uv) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const Vec2 mid = 0.5 * (lo + hi);
  const double size = std::max((hi - lo).maxCoeff(), std::numeric_limits<double>::min());
  auto basis = [&](int v) {
    const Vec2 z = (uv[v] - mid) / size;
    return Eigen::Vector3d(1.0, z.x(), z.y());
  };
  // Groups having each vertex as a corner; the first one represents the vertex.
  std::vector<std::vector<int>> vertex_groups(V);
  for (int t = 0; t < T; ++t) {
    const int g = groups.find(t);
    for (int i = 0; i < 3; ++i) {
      auto& list = vertex_groups[triangles[t][i]];
      if (std::find(list.begin(), list.end(), g) == list.end()) list.push_back(g);
    }
  }

  // Constraint rows, each a short list of (group root, 3 coefficients), unit norm; terms
  // on main groups are dropped (their a_g is 0).
  using Row = std::vector<std::pair<int, Eigen::Vector3d>>;
  std::vector<Row> rows;
  auto add_row = [&](Row row, double scale) {
    double norm_sq = 0.0;
    for (const auto& term : row) norm_sq += term.second.squaredNorm();
    const double norm = std::sqrt(norm_sq);
    // A row much smaller than its terms is round-off of a zero row.
    if (!(norm > 1e-9 * scale)) return;
    Row kept;
    for (auto& term : row) {
      if (!main[term.first]) kept.emplace_back(term.first, term.second / norm);
    }
    if (!kept.empty()) rows.push_back(std::move(kept));
  };
  auto accumulate = [](Row& row, int g, const Eigen::Vector3d& c) {
    for (auto& term : row) {
      if (term.first == g) {
        term.second += c;
        return;
      }
    }
    row.emplace_back(g, c);
  };
  for (int v = 0; v < V; ++v) {
    const auto& list = vertex_groups[v];
    for (size_t i = 1; i < list.size(); ++i) {
      add_row({{list[0], basis(v)}, {list[i], -basis(v)}}, 2.0 * basis(v).norm());
    }
  }
  for (int t = 0; t < T; ++t) {
    auto node = [&](int n) { return n < 3 ? triangles[t][n] : extras[t][n - 3]; };
    bool spans = false;
    for (int n = 1; n < fits[t].count; ++n) {
      spans = spans || vertex_groups[node(n)][0] != vertex_groups[node(0)][0];
    }
    if (!spans) continue;
    for (int c = 0; c < 3; ++c) {
      Row row;
      double scale = 0.0;
      for (int n = 0; n < fits[t].count; ++n) {
        const Eigen::Vector3d term = fits[t].w[c][n] * basis(node(n));
        accumulate(row, vertex_groups[node(n)][0], term);
        scale += term.norm();
      }
      add_row(std::move(row), scale);
    }
  }

  // Clusters of non-main groups coupled by rows; each must have full column rank.
  DisjointSets clusters(T);
  for (const Row& row : rows) {
    for (size_t i = 1; i < row.size(); ++i) clusters.unite(row[0].first, row[i].first);
  }
  std::vector<int> column(T, -1), cluster_size(T, 0);
  for (int t = 0; t < T; ++t) {
    const int g = groups.find(t);
    if (g != t || main[g]) continue;  // one entry per non-main group
    column[g] = cluster_size[clusters.find(g)]++;
  }
  std::vector<std::vector<int>> cluster_rows(T);
  for (int r = 0; r < static_cast<int>(rows.size()); ++r) {
    cluster_rows[clusters.find(rows[r][0].first)].push_back(r);
  }
  for (int root = 0; root < T; ++root) {
    const int n = cluster_size[root];
    if (n == 0) continue;
    if (n > kMaxClusterGroups) return false;
    Eigen::MatrixXd C = Eigen::MatrixXd::Zero(cluster_rows[root].size(), 3 * n);
    for (size_t r = 0; r < cluster_rows[root].size(); ++r) {
      for (const auto& [g, c] : rows[cluster_rows[root][r]]) {
        C.block<1, 3>(r, 3 * column[g]) = c.transpose();
      }
    }
    if (C.rows() < C.cols()) return false;
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(C);
    qr.setThreshold(1e-10);
    if (qr.rank() < C.cols()) return false;
  }
  return true;
}

// Sparse weights over vertices: value = sum_n weight[n] x[vertex[n]].
struct Weights {
  std::vector<int> vertex;
  std::vector<double> weight;
  void add(int v, double w) {
    for (size_t n = 0; n < vertex.size(); ++n) {
      if (vertex[n] == v) {
        weight[n] += w;
        return;
      }
    }
    vertex.push_back(v);
    weight.push_back(w);
  }
};

// The triangles' Hessians in flux form: H_T = 1/A_T sum_e l_e G_e n_e^T (symmetric part),
// over T's edges e of length l_e and outward normal n_e, G_e being the mean gradient of the
// patches of e's triangles at e's midpoint. Exact for quadratic fields (each patch is, and
// the midpoint rule integrates the linear gradient of a quadratic exactly over an edge), and
// the Hessians of neighbouring triangles share their edge gradients, so that summed over
// any region, A_T H_T leaves only the flux through the region's boundary: no pattern of
// vertex values (a checkerboard on a grid) can pass for a curvature the size of the region.
std::vector<BendingStencil> flux_hessians(const TriList& triangles, const Vec2List& uv,
                                          const MeshAdjacency& adj,
                                          const std::vector<std::vector<int>>& extras,
                                          const std::vector<Fit>& fits,
                                          const std::vector<uint8_t>& own_hessian,
                                          const std::vector<uint8_t>& clamped,
                                          int* patch_hessians) {
  const int T = static_cast<int>(triangles.size());
  auto node = [&](int t, int n) { return n < 3 ? triangles[t][n] : extras[t][n - 3]; };
  // The patch's own (constant) Hessian as the triangle's stencil.
  auto patch_stencil = [&](int t, double area) {
    BendingStencil st;
    st.area = area;
    for (int n = 0; n < fits[t].count; ++n) {
      st.vertex.push_back(node(t, n));
      st.w_uu.push_back(fits[t].w[0][n]);
      st.w_vv.push_back(fits[t].w[1][n]);
      st.w_uv.push_back(fits[t].w[2][n]);
    }
    return st;
  };
  // Gradient weights (u and v components) of t's patch at point m.
  auto patch_gradient = [&](int t, const Vec2& m, Weights grad[2]) {
    const Tri& tri = triangles[t];
    const Vec2 d = m - (uv[tri[0]] + uv[tri[1]] + uv[tri[2]]) / 3.0;
    const Fit& fit = fits[t];
    for (int n = 0; n < fit.count; ++n) {
      const double gu = fit.g[0][n] + fit.w[0][n] * d.x() + fit.w[2][n] * d.y();
      const double gv = fit.g[1][n] + fit.w[2][n] * d.x() + fit.w[1][n] * d.y();
      grad[0].add(node(t, n), gu);
      grad[1].add(node(t, n), gv);
    }
  };
  // Mean patch gradient at each edge's midpoint.
  std::map<std::pair<int, int>, std::array<Weights, 2>> edge_gradient;
  for (const auto& [edge, tris] : adj.edge_triangles) {
    const Vec2 m = 0.5 * (uv[edge.first] + uv[edge.second]);
    std::array<Weights, 2> sum;
    // Beside a clamped triangle the gradient is the clamp's (its linear interpolant's).
    int count = 0;
    for (int t : tris) {
      if (!clamped[t]) continue;
      const Tri& tri = triangles[t];
      const Vec2 p[3] = {uv[tri[0]], uv[tri[1]], uv[tri[2]]};
      Vec2 g[3];  // the linear interpolant's gradient is sum_i g_i x_i
      barycentric_gradients(p, cross2(p[1] - p[0], p[2] - p[0]), g);
      for (int i = 0; i < 3; ++i) {
        sum[0].add(tri[i], g[i].x());
        sum[1].add(tri[i], g[i].y());
      }
      ++count;
    }
    if (count == 0) {
      for (int t : tris) patch_gradient(t, m, sum.data());
      count = static_cast<int>(tris.size());
    }
    for (auto& component : sum) {
      for (double& w : component.weight) w /= static_cast<double>(count);
    }
    edge_gradient.emplace(edge, std::move(sum));
  }
  std::vector<BendingStencil> stencils(T);
  for (int t = 0; t < T; ++t) {
    const Tri& tri = triangles[t];
    const Vec2 p[3] = {uv[tri[0]], uv[tri[1]], uv[tri[2]]};
    const double d = cross2(p[1] - p[0], p[2] - p[0]);  // twice the signed area, m^2
    const double area = 0.5 * std::abs(d);
    BendingStencil& st = stencils[t];
    st.area = area;
    if (clamped[t]) continue;  // held rigid: no bending
    if (own_hessian[t]) {
      *patch_hessians += 1;
      st = patch_stencil(t, area);
      continue;
    }
    const double orientation = d > 0 ? 1 : -1;
    Weights h[3];  // uu, vv, uv
    for (int k = 0; k < 3; ++k) {
      const int a = tri[(k + 1) % 3], b = tri[(k + 2) % 3];
      const Vec2 e = uv[b] - uv[a];
      const Vec2 ln = orientation * Vec2(e.y(), -e.x()) / area;  // l_e n_e / A_T, 1/m
      const auto& G = edge_gradient.at({std::min(a, b), std::max(a, b)});
      for (size_t n = 0; n < G[0].vertex.size(); ++n) {
        h[0].add(G[0].vertex[n], ln.x() * G[0].weight[n]);
        h[2].add(G[0].vertex[n], 0.5 * ln.y() * G[0].weight[n]);
      }
      for (size_t n = 0; n < G[1].vertex.size(); ++n) {
        h[1].add(G[1].vertex[n], ln.y() * G[1].weight[n]);
        h[2].add(G[1].vertex[n], 0.5 * ln.x() * G[1].weight[n]);
      }
    }
    Weights all;
    for (const Weights& c : h) {
      for (int v : c.vertex) all.add(v, 0.0);
    }
    st.vertex = all.vertex;
    auto dense = [&](const Weights& c) {
      std::vector<double> w(st.vertex.size(), 0.0);
      for (size_t n = 0; n < c.vertex.size(); ++n) {
        const size_t i = std::find(st.vertex.begin(), st.vertex.end(), c.vertex[n]) - st.vertex.begin();
        w[i] = c.weight[n];
      }
      return w;
    };
    st.w_uu = dense(h[0]);
    st.w_vv = dense(h[1]);
    st.w_uv = dense(h[2]);
    const double l2 = mean_squared_edge(p);
    double sum_sq = 0.0;
    for (size_t n = 0; n < st.vertex.size(); ++n) {
      sum_sq += st.w_uu[n] * st.w_uu[n] + st.w_vv[n] * st.w_vv[n] + st.w_uv[n] * st.w_uv[n];
    }
    // Cap triangles: 1/A_T amplifies the differences of the edge gradients (|w| l^2 of
    // 3000 measured on the project's sliver mesh, 5-9 elsewhere); their own patch is better.
    const double amplification = l2 * std::sqrt(sum_sq);
    if (amplification > kMaxAmplification && amplification > fits[t].amplification) {
      *patch_hessians += 1;
      st = patch_stencil(t, area);
    }
  }
  return stencils;
}

}  // namespace

BendingStencils build_bending_stencils(const TriList& triangles, const Vec2List& rest_uv,
                                       const std::vector<uint8_t>& pinned) {
  BendingStencils built;
  const int V = static_cast<int>(rest_uv.size());
  const int T = static_cast<int>(triangles.size());

  for (int t = 0; t < T; ++t) {
    for (int i = 0; i < 3; ++i) {
      if (triangles[t][i] < 0 || triangles[t][i] >= V) {
        throw InputError("bending: triangle " + std::to_string(t) + " has vertex id " +
                         std::to_string(triangles[t][i]) + " outside [0, " + std::to_string(V) +
                         ")");
      }
    }
    const Vec2 p[3] = {rest_uv[triangles[t][0]], rest_uv[triangles[t][1]],
                       rest_uv[triangles[t][2]]};
    const double scale =
        (p[1] - p[0]).squaredNorm() + (p[2] - p[1]).squaredNorm() + (p[0] - p[2]).squaredNorm();
    if (!(std::abs(cross2(p[1] - p[0], p[2] - p[0])) > 1e-12 * scale)) {
      throw InputError("bending: rest triangle " + std::to_string(t) + " is degenerate");
    }
  }
  const MeshAdjacency adj = build_adjacency(triangles, V);

  // Extra stencil points of every triangle: normally its hinge apices. Triangles with a
  // boundary (or non-manifold) edge keep their apices and complete them with the best
  // nearby vertices; interior triangles with ill-posed apices choose the best nearby set
  // that still contains one apex. If the weights stay large (needle or cap triangles),
  // a least-squares patch over the nearby vertices replaces the interpolating one.
  std::vector<std::vector<int>> extras(T), apices(T), interpolating(T);
  std::vector<uint8_t> fallback(T, 0), least_squares(T, 0);
  std::vector<Fit> fits(T);
  auto corners = [&](int t, Vec2 p[3]) {
    for (int i = 0; i < 3; ++i) p[i] = rest_uv[triangles[t][i]];
  };
  for (int t = 0; t < T; ++t) {
    Vec2 p[3];
    corners(t, p);
    apices[t] = hinge_apices(triangles, adj, t);
    if (apices[t].size() < 3) {
      extras[t] = search_extras(triangles, rest_uv, adj, t, p, apices[t], apices[t], false);
      ++built.boundary_stencils;
    } else if (well_posed(fit_hessian(p, positions(rest_uv, apices[t])))) {
      extras[t] = apices[t];
    } else {
      extras[t] = search_extras(triangles, rest_uv, adj, t, p, {}, apices[t], true);
      fallback[t] = 1;
    }
    interpolating[t] = extras[t];
    fits[t] = fit_hessian(p, positions(rest_uv, extras[t]));
    if (fits[t].amplification > kMaxAmplification) {
      const std::vector<int> nearby = candidate_vertices(triangles, rest_uv, adj, t);
      if (nearby.size() >= 3) {
        const Fit wide = fit_least_squares(p, positions(rest_uv, nearby));
        if (wide.conditioning > 1e-8 && wide.amplification < fits[t].amplification) {
          extras[t] = nearby;
          fits[t] = wide;
          least_squares[t] = 1;
        }
      }
    }
  }
  // Fallback and least-squares stencils may break the ties that make the kernel of Q
  // exactly affine (see kernel_is_affine). Until it is, such stencils go back to their
  // interpolating patch, then to their hinge apices, which tie a triangle to all its
  // neighbours: first those touching a vertex outside the largest tied group, least-squares
  // ones first; if there are none, those bordering another group.
  while (true) {
    DisjointSets groups = stencil_groups(triangles, adj, extras, least_squares);
    if (kernel_is_affine(triangles, rest_uv, adj, groups, extras, fits)) break;
    const std::vector<uint8_t> untied =
        untied_vertices(triangles, groups, main_groups(triangles, adj, groups), V);
    auto touches_untied = [&](int t) {
      return untied[triangles[t][0]] || untied[triangles[t][1]] || untied[triangles[t][2]];
    };
    auto borders_group = [&](int t) {
      for (int k = 0; k < 3; ++k) {
        const int other = hinge(triangles, adj, t, k).first;
        if (other >= 0 && groups.find(other) != groups.find(t)) return true;
      }
      return false;
    };
    std::vector<int> revert;
    for (auto select : {0, 1, 2, 3}) {
      for (int t = 0; t < T; ++t) {
        const bool kind = select % 2 == 0 ? least_squares[t] != 0 : fallback[t] != 0;
        const bool where = select < 2 ? touches_untied(t) : borders_group(t);
        if (kind && where) revert.push_back(t);
      }
      if (!revert.empty()) break;
    }
    if (revert.empty()) break;  // nothing left to revert
    for (int t : revert) {
      Vec2 p[3];
      corners(t, p);
      if (least_squares[t]) {
        extras[t] = interpolating[t];
        least_squares[t] = 0;
      } else {
        extras[t] = apices[t];
        fallback[t] = 0;
      }
      fits[t] = fit_hessian(p, positions(rest_uv, extras[t]));
    }
  }
  for (int t = 0; t < T; ++t) {
    built.fallback_stencils += fallback[t];
    built.least_squares_stencils += least_squares[t];
  }

  // Each triangle's patch gives a gradient everywhere: at its centroid (fit.g) plus its
  // constant Hessian (fit.w) times the offset. The gradient at an edge's midpoint is the
  // mean of the patches of the triangles sharing the edge; the triangle's Hessian is then
  // the flux of these edge gradients through its boundary (see flux_hessians).
  std::vector<uint8_t> clamped(T, 0);
  if (!pinned.empty()) {
    for (int t = 0; t < T; ++t) {
      clamped[t] = pinned[triangles[t][0]] && pinned[triangles[t][1]] && pinned[triangles[t][2]];
      built.clamped_triangles += clamped[t];
    }
  }
  built.stencils = flux_hessians(triangles, rest_uv, adj, extras, fits, least_squares, clamped,
                                 &built.patch_hessians);
  for (const Fit& fit : fits) built.max_amplification = std::max(built.max_amplification, fit.amplification);
  return built;
}

}  // namespace tissu
