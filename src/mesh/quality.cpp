#include "mesh/quality.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace tissu {
namespace {

struct Edge {
  int lo, hi;  // sorted ids
  int from, to;  // as in the triangle
};

// All triangle edges, sorted so that copies of an undirected edge are adjacent.
std::vector<Edge> sorted_edges(const TriList& triangles) {
  std::vector<Edge> edges;
  edges.reserve(3 * triangles.size());
  for (const Tri& t : triangles) {
    for (int k = 0; k < 3; ++k) {
      const int a = t[k], b = t[(k + 1) % 3];
      edges.push_back({std::min(a, b), std::max(a, b), a, b});
    }
  }
  std::sort(edges.begin(), edges.end(), [](const Edge& x, const Edge& y) {
    return x.lo != y.lo ? x.lo < y.lo : x.hi < y.hi;
  });
  return edges;
}

double angle_between(const Vec2& a, const Vec2& b) {
  return std::atan2(std::abs(a.x() * b.y() - a.y() * b.x()), a.dot(b));
}

}  // namespace

double uv_area(const TriMesh& mesh, const Tri& t) {
  const Vec2 ab = mesh.rest_uv[t[1]] - mesh.rest_uv[t[0]];
  const Vec2 ac = mesh.rest_uv[t[2]] - mesh.rest_uv[t[0]];
  return 0.5 * (ab.x() * ac.y() - ab.y() * ac.x());
}

std::vector<std::pair<int, int>> boundary_edges(const TriList& triangles) {
  const std::vector<Edge> edges = sorted_edges(triangles);
  std::vector<std::pair<int, int>> boundary;
  for (size_t i = 0; i < edges.size();) {
    size_t j = i;
    while (j < edges.size() && edges[j].lo == edges[i].lo && edges[j].hi == edges[i].hi) ++j;
    if (j - i == 1) boundary.emplace_back(edges[i].from, edges[i].to);
    i = j;
  }
  return boundary;
}

MeshQuality measure_quality(const TriMesh& mesh) {
  MeshQuality q;
  q.vertex_count = static_cast<int>(mesh.rest_uv.size());
  q.triangle_count = static_cast<int>(mesh.triangles.size());
  if (mesh.triangles.empty()) return q;

  q.min_angle_deg = 180;
  q.min_area = std::numeric_limits<double>::infinity();
  q.max_area = -q.min_area;
  double deviation_sum = 0, aspect_sum = 0;
  for (const Tri& t : mesh.triangles) {
    const Vec2 &a = mesh.rest_uv[t[0]], &b = mesh.rest_uv[t[1]], &c = mesh.rest_uv[t[2]];
    const std::array<double, 3> angles = {angle_between(b - a, c - a) * 180 / kPi,
                                          angle_between(c - b, a - b) * 180 / kPi,
                                          angle_between(a - c, b - c) * 180 / kPi};
    for (double angle : angles) {
      q.min_angle_deg = std::min(q.min_angle_deg, angle);
      q.max_angle_deg = std::max(q.max_angle_deg, angle);
      deviation_sum += std::abs(angle - 60);
    }
    const double area = uv_area(mesh, t);
    const double longest2 =
        std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
    // longest / (2 area / longest) * sqrt(3) / 2
    const double aspect = area > 0 ? longest2 * std::sqrt(3.0) / (4 * area)
                                   : std::numeric_limits<double>::infinity();
    q.max_aspect_ratio = std::max(q.max_aspect_ratio, aspect);
    aspect_sum += aspect;
    q.min_area = std::min(q.min_area, area);
    q.max_area = std::max(q.max_area, area);
    q.total_area += area;
  }
  q.mean_angle_deviation_deg = deviation_sum / (3.0 * q.triangle_count);
  q.mean_aspect_ratio = aspect_sum / q.triangle_count;

  // Valence over unique edges; boundary vertices are those on an edge used once.
  const std::vector<Edge> edges = sorted_edges(mesh.triangles);
  std::vector<int> valence(q.vertex_count, 0);
  std::vector<char> on_boundary(q.vertex_count, 0);
  std::array<int, 36> direction_bins{};
  int unique_edges = 0;
  for (size_t i = 0; i < edges.size();) {
    size_t j = i;
    while (j < edges.size() && edges[j].lo == edges[i].lo && edges[j].hi == edges[i].hi) ++j;
    const int lo = edges[i].lo, hi = edges[i].hi;
    ++valence[lo];
    ++valence[hi];
    if (j - i == 1) on_boundary[lo] = on_boundary[hi] = 1;
    const Vec2 d = mesh.rest_uv[hi] - mesh.rest_uv[lo];
    double degrees = std::atan2(d.y(), d.x()) * 180 / kPi;
    if (degrees < 0) degrees += 180;
    // Bins centred on multiples of 5 deg, so grid directions sit mid-bin.
    ++direction_bins[static_cast<int>(std::floor(degrees / 5 + 0.5)) % 36];
    ++unique_edges;
    i = j;
  }
  int interior = 0, valence6 = 0;
  for (int v = 0; v < q.vertex_count; ++v) {
    if (on_boundary[v] || valence[v] == 0) continue;
    if (valence[v] >= static_cast<int>(q.interior_valence_histogram.size())) {
      q.interior_valence_histogram.resize(valence[v] + 1, 0);
    }
    ++q.interior_valence_histogram[valence[v]];
    ++interior;
    valence6 += valence[v] == 6;
  }
  q.interior_valence6_fraction = interior > 0 ? static_cast<double>(valence6) / interior : 0;
  std::sort(direction_bins.rbegin(), direction_bins.rend());
  q.edge_direction_concentration =
      static_cast<double>(direction_bins[0] + direction_bins[1] + direction_bins[2] +
                          direction_bins[3]) /
      unique_edges;
  return q;
}

}  // namespace tissu
