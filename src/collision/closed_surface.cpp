#include "collision/closed_surface.h"

#include <algorithm>
#include <cmath>

#include "collision/crossings.h"
#include "collision/primitive_distance.h"
#include "core/error.h"

namespace tissu {

namespace {

// A triangle below this area / (longest edge)^2 has collinear corners up to rounding.
constexpr double kZeroAreaRatio = 1e-12;
// Cells along the longest side of the far-field grid.
constexpr int kGridCells = 32;

std::string triangle_name(const std::vector<std::string>& places, size_t t) {
  return places.empty() ? "triangle " + std::to_string(t) : places[t];
}

std::string edge_name(int a, int b) {
  return "edge between vertex ids " + std::to_string(std::min(a, b)) + " and " +
         std::to_string(std::max(a, b));
}

}  // namespace

ClosedSurface::ClosedSurface(Vec3List vertices, TriList triangles, const std::string& source,
                             const std::vector<std::string>& places)
    : vertices_(std::move(vertices)), triangles_(std::move(triangles)) {
  check_topology(source, places);
  compute_normals();
  std::vector<Box3> boxes(triangles_.size());
  for (size_t t = 0; t < triangles_.size(); ++t) {
    Box3 box(vertices_[triangles_[t][0]]);
    box.extend(vertices_[triangles_[t][1]]);
    box.extend(vertices_[triangles_[t][2]]);
    boxes[t] = box;
  }
  tree_.build(boxes);
  wide_ = WideBvh(tree_);
  self_crossings_ = tissu::self_crossings(vertices_, triangles_);
  build_far_grid();
}

void ClosedSurface::check_topology(const std::string& source,
                                   const std::vector<std::string>& places) {
  auto fail = [&](const std::string& problem) { throw InputError(source + ": " + problem); };
  const long long nv = static_cast<long long>(vertices_.size());
  const size_t nt = triangles_.size();
  if (nt == 0) fail("contains no triangles");
  for (long long v = 0; v < nv; ++v) {
    if (!vertices_[v].allFinite()) fail("vertex id " + std::to_string(v) + ": non-finite position");
  }
  for (size_t t = 0; t < nt; ++t) {
    const Tri& tri = triangles_[t];
    for (int k = 0; k < 3; ++k) {
      if (tri[k] < 0 || tri[k] >= nv) {
        fail(triangle_name(places, t) + ": vertex id " + std::to_string(tri[k]) +
             " out of range (" + std::to_string(nv) + " vertices)");
      }
    }
    if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2]) {
      fail(triangle_name(places, t) + ": uses a vertex twice");
    }
    const Vec3 &a = vertices_[tri[0]], &b = vertices_[tri[1]], &c = vertices_[tri[2]];
    const double longest = std::max({(b - a).squaredNorm(), (c - b).squaredNorm(),
                                     (a - c).squaredNorm()});
    if (!(0.5 * (b - a).cross(c - a).norm() > kZeroAreaRatio * longest)) {
      fail(triangle_name(places, t) + ": zero area (its corners are collinear)");
    }
  }

  // Every edge must border exactly two triangles that run along it in opposite directions.
  struct HalfEdge {
    int lo, hi, triangle, corner;
    bool forward;  // runs lo -> hi
  };
  std::vector<HalfEdge> half(3 * nt);
  for (size_t t = 0; t < nt; ++t) {
    for (int k = 0; k < 3; ++k) {
      const int a = triangles_[t][k], b = triangles_[t][(k + 1) % 3];
      half[3 * t + k] = {std::min(a, b), std::max(a, b), static_cast<int>(t), k, a < b};
    }
  }
  std::sort(half.begin(), half.end(), [](const HalfEdge& x, const HalfEdge& y) {
    return x.lo < y.lo || (x.lo == y.lo && (x.hi < y.hi || (x.hi == y.hi && x.triangle < y.triangle)));
  });
  triangle_edges_.assign(nt, {-1, -1, -1});
  std::vector<std::array<int, 2>> edge_triangles;
  for (size_t i = 0; i < half.size();) {
    size_t j = i;
    while (j < half.size() && half[j].lo == half[i].lo && half[j].hi == half[i].hi) ++j;
    const std::string edge = edge_name(half[i].lo, half[i].hi);
    if (j - i == 1) {
      fail("not closed: the " + edge + " borders only " + triangle_name(places, half[i].triangle) +
           " (mesh obstacles must be closed surfaces)");
    }
    if (j - i > 2) {
      fail("non-manifold: the " + edge + " borders " + std::to_string(j - i) + " triangles (" +
           triangle_name(places, half[i].triangle) + ", " +
           triangle_name(places, half[i + 1].triangle) + ", " +
           triangle_name(places, half[i + 2].triangle) + ")");
    }
    if (half[i].forward == half[i + 1].forward) {
      fail(triangle_name(places, half[i].triangle) + " and " +
           triangle_name(places, half[i + 1].triangle) + " are ordered against each other across the " +
           edge + " (inconsistent orientation)");
    }
    const int id = static_cast<int>(edges_.size());
    edges_.push_back({half[i].lo, half[i].hi});
    edge_triangles.push_back({half[i].triangle, half[i + 1].triangle});
    triangle_edges_[half[i].triangle][half[i].corner] = id;
    triangle_edges_[half[i + 1].triangle][half[i + 1].corner] = id;
    i = j;
  }

  // Around every vertex the triangles must form one fan: walking across the edges that
  // leave the vertex must reach all of them.
  std::vector<int> degree(nv, 0), first_triangle(nv, -1);
  for (size_t t = 0; t < nt; ++t) {
    for (int k = 0; k < 3; ++k) {
      ++degree[triangles_[t][k]];
      if (first_triangle[triangles_[t][k]] < 0) first_triangle[triangles_[t][k]] = static_cast<int>(t);
    }
  }
  for (long long v = 0; v < nv; ++v) {
    if (degree[v] == 0) continue;
    int t = first_triangle[v], steps = 0;
    do {
      const int k = triangles_[t][0] == v ? 0 : triangles_[t][1] == v ? 1 : 2;
      const std::array<int, 2>& across = edge_triangles[triangle_edges_[t][k]];
      t = across[0] == t ? across[1] : across[0];
      ++steps;
    } while (t != first_triangle[v] && steps <= degree[v]);
    if (steps != degree[v]) {
      fail("non-manifold: separate fans of triangles meet at vertex id " + std::to_string(v));
    }
  }

  // Enclosed volume (divergence theorem); negative: every triangle faces inward.
  double six_volume = 0.0;
  for (const Tri& tri : triangles_) {
    six_volume += vertices_[tri[0]].dot(vertices_[tri[1]].cross(vertices_[tri[2]]));
  }
  if (six_volume < 0.0) {
    reversed_ = true;
    six_volume = -six_volume;
    for (size_t t = 0; t < nt; ++t) {
      std::swap(triangles_[t][1], triangles_[t][2]);
      // Corners b and c swapped: edges ab, bc, ca become ac, cb, ba.
      std::swap(triangle_edges_[t][0], triangle_edges_[t][2]);
    }
  }
  volume_ = six_volume / 6.0;
}

void ClosedSurface::compute_normals() {
  const size_t nt = triangles_.size();
  face_normals_.resize(nt);
  edge_normals_.assign(edges_.size(), Vec3::Zero());
  vertex_normals_.assign(vertices_.size(), Vec3::Zero());
  for (size_t t = 0; t < nt; ++t) {
    const Tri& tri = triangles_[t];
    const Vec3 n = (vertices_[tri[1]] - vertices_[tri[0]])
                       .cross(vertices_[tri[2]] - vertices_[tri[0]])
                       .normalized();
    face_normals_[t] = n;
    for (int k = 0; k < 3; ++k) {
      edge_normals_[triangle_edges_[t][k]] += n;
      const Vec3 e1 = vertices_[tri[(k + 1) % 3]] - vertices_[tri[k]];
      const Vec3 e2 = vertices_[tri[(k + 2) % 3]] - vertices_[tri[k]];
      vertex_normals_[tri[k]] += std::atan2(e1.cross(e2).norm(), e1.dot(e2)) * n;
    }
  }
  // Sharp convex edges: the third corner of one triangle lies below the other's plane.
  std::vector<std::array<int, 2>> edge_triangles(edges_.size(), {-1, -1});
  for (size_t t = 0; t < nt; ++t) {
    for (int k = 0; k < 3; ++k) {
      auto& pair = edge_triangles[triangle_edges_[t][k]];
      pair[pair[0] < 0 ? 0 : 1] = static_cast<int>(t);
    }
  }
  const double cos_sharp = std::cos(kSharpAngle);
  for (size_t e = 0; e < edges_.size(); ++e) {
    const int t0 = edge_triangles[e][0], t1 = edge_triangles[e][1];
    if (face_normals_[t0].dot(face_normals_[t1]) > cos_sharp) continue;
    const Tri& other = triangles_[t1];
    int opposite = other[0];
    for (int k = 0; k < 3; ++k) {
      if (other[k] != edges_[e][0] && other[k] != edges_[e][1]) opposite = other[k];
    }
    if ((vertices_[opposite] - vertices_[edges_[e][0]]).dot(face_normals_[t0]) >= 0.0) continue;
    sharp_edges_.push_back(static_cast<int>(e));
  }
}

double ClosedSurface::distance2_to(int triangle, const Vec3& p) const {
  const Tri& tri = triangles_[triangle];
  return (p - closest_on_triangle(p, vertices_[tri[0]], vertices_[tri[1]], vertices_[tri[2]])
                  .point)
      .squaredNorm();
}

SurfaceQuery ClosedSurface::closest_bounded(const Vec3& p, double max_distance2,
                                            int hint) const {
  // The hinted triangle bounds the search; only a strictly nearer one replaces it.
  int t = -1;
  if (hint >= 0 && hint < static_cast<int>(triangles_.size())) {
    const double d2 = distance2_to(hint, p);
    if (d2 < max_distance2) {
      max_distance2 = d2;
      t = hint;
    }
  }
  double best2 = 0.0;
  const int found = wide_.nearest(
      p, max_distance2, [&](int id, const Vec3& q) { return distance2_to(id, q); }, &best2);
  if (found >= 0) t = found;
  SurfaceQuery out;
  if (t < 0) return out;
  const Tri& tri = triangles_[t];
  const TrianglePoint q =
      closest_on_triangle(p, vertices_[tri[0]], vertices_[tri[1]], vertices_[tri[2]]);
  Vec3 pseudo;
  switch (q.feature) {
    case TriangleFeature::Face: pseudo = face_normals_[t]; break;
    case TriangleFeature::EdgeAB: pseudo = edge_normals_[triangle_edges_[t][0]]; break;
    case TriangleFeature::EdgeBC: pseudo = edge_normals_[triangle_edges_[t][1]]; break;
    case TriangleFeature::EdgeCA: pseudo = edge_normals_[triangle_edges_[t][2]]; break;
    case TriangleFeature::VertexA: pseudo = vertex_normals_[tri[0]]; break;
    case TriangleFeature::VertexB: pseudo = vertex_normals_[tri[1]]; break;
    case TriangleFeature::VertexC: pseudo = vertex_normals_[tri[2]]; break;
  }
  const Vec3 away = p - q.point;
  const double length = away.norm();
  const double sign = away.dot(pseudo) < 0.0 ? -1.0 : 1.0;
  out.distance = sign * length;
  out.point = q.point;
  out.triangle = t;
  out.normal = length > 0.0 ? Vec3(sign * away / length) : Vec3(pseudo.normalized());
  return out;
}

SurfaceQuery ClosedSurface::closest(const Vec3& p, int hint) const {
  return closest_bounded(p, INFINITY, hint);
}

void ClosedSurface::build_far_grid() {
  const Box3& b = tree_.bounds();
  const double side = b.sizes().maxCoeff();
  cell_ = side / (kGridCells - 4);
  const Vec3 margin = Vec3::Constant(2.0 * cell_);
  grid_origin_ = b.min() - margin;
  const Vec3 span = b.sizes() + 2.0 * margin;
  for (int a = 0; a < 3; ++a) cells_[a] = std::max(1, static_cast<int>(std::ceil(span[a] / cell_)));
  cell_distance_.resize(static_cast<size_t>(cells_[0]) * cells_[1] * cells_[2]);
  size_t index = 0;
  for (int k = 0; k < cells_[2]; ++k) {
    for (int j = 0; j < cells_[1]; ++j) {
      for (int i = 0; i < cells_[0]; ++i) {
        const Vec3 centre = grid_origin_ + cell_ * Vec3(i + 0.5, j + 0.5, k + 0.5);
        cell_distance_[index++] = static_cast<float>(closest(centre).distance);
      }
    }
  }
}

SurfaceQuery ClosedSurface::closest_within(const Vec3& p, double reach, int hint) const {
  // Far from the surface's box: outside, at least that far.
  const double outside = bounds().exteriorDistance(p);
  if (outside > 0.0 && outside >= reach) {
    SurfaceQuery far;
    far.distance = outside;
    far.normal = (p - bounds().center()).normalized();
    far.point = p;
    return far;
  }
  const Vec3 g = (p - grid_origin_) / cell_;
  const int i = static_cast<int>(std::floor(g.x())), j = static_cast<int>(std::floor(g.y())),
            k = static_cast<int>(std::floor(g.z()));
  if (i < 0 || j < 0 || k < 0 || i >= cells_[0] || j >= cells_[1] || k >= cells_[2]) {
    return closest(p, hint);
  }
  // The distance is 1-Lipschitz: within a cell it differs from the centre's by at most
  // half the cell diagonal (plus the float rounding of the stored value).
  const double centre = cell_distance_[(static_cast<size_t>(k) * cells_[1] + j) * cells_[0] + i];
  const double slack = 0.8660254037844386 * cell_ + 1e-6 * std::fabs(centre) + 1e-9;
  const double lower = std::fabs(centre) - slack;
  if (lower > 0.0 && lower >= reach) {
    SurfaceQuery far;
    far.distance = centre < 0.0 ? -lower : lower;
    far.normal = (p - bounds().center()).normalized();
    far.point = p;
    return far;
  }
  const double upper = std::fabs(centre) + slack;
  const SurfaceQuery near = closest_bounded(p, upper * upper, hint);
  return near.triangle >= 0 ? near : closest(p, hint);
}

}  // namespace tissu
