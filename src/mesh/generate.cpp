#include "mesh/generate.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.h"
#include "mesh/format.h"
#include "mesh/graded_disk.h"
#include "mesh/irregular.h"

namespace tissu {
namespace {

constexpr int kMaxTriangles = 5'000'000;

void require_length(const char* what, const char* name, double value) {
  if (!(std::isfinite(value) && value > 0)) {
    throw InputError(std::string(what) + ": " + name + " must be a positive length in m, got " +
                     format_short(value));
  }
}

void require_count(const char* what, int triangles, int minimum) {
  if (triangles < minimum || triangles > kMaxTriangles) {
    throw InputError(std::string(what) + ": triangles must be between " +
                     std::to_string(minimum) + " and " + std::to_string(kMaxTriangles) +
                     ", got " + std::to_string(triangles));
  }
}

// A disk with an inner circle: a radius, at least two rings' triangles, 0 < inner < radius.
void require_disk(double radius, int triangles, double inner_radius) {
  require_length("generate_disk", "radius", radius);
  require_count("generate_disk", triangles, 24);  // two rings at least
  if (!(inner_radius > 0.0 && inner_radius < radius)) {
    throw InputError("generate_disk: inner_radius must be between 0 and the radius " +
                     format_short(radius) + " m, got " + format_short(inner_radius));
  }
}

TriMesh flat_mesh(Vec2List points, TriList triangles) {
  TriMesh mesh;
  mesh.positions.reserve(points.size());
  for (const Vec2& p : points) mesh.positions.emplace_back(p.x(), p.y(), 0.0);
  mesh.rest_uv = std::move(points);
  mesh.triangles = std::move(triangles);
  return mesh;
}

// Edge length (m) of equilateral triangles that tile `area` (m^2) with `triangles` of them.
double equilateral_spacing(double area, int triangles) {
  return std::sqrt(4.0 * area / (std::sqrt(3.0) * triangles));
}

// Coordinate i of n equal steps from -length/2 to length/2, with both ends exact.
double grid_coordinate(double length, int i, int n) {
  if (i == n) return 0.5 * length;
  return -0.5 * length + length * i / n;
}

// Cell (i, j) of an nx x ny grid of vertices (i, j) -> j * (nx + 1) + i, cut along the
// diagonal through (i, j) when i + j is even, through (i + 1, j) otherwise.
TriList union_jack_triangles(int nx, int ny) {
  TriList triangles;
  triangles.reserve(2 * static_cast<size_t>(nx) * ny);
  auto id = [nx](int i, int j) { return j * (nx + 1) + i; };
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const int a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
      if ((i + j) % 2 == 0) {
        triangles.emplace_back(a, b, c);
        triangles.emplace_back(a, c, d);
      } else {
        triangles.emplace_back(a, b, d);
        triangles.emplace_back(b, c, d);
      }
    }
  }
  return triangles;
}

// Grid cell counts with 2 * nx * ny close to `triangles` and nx / ny close to width / height.
std::pair<int, int> grid_shape(double width, double height, int triangles) {
  const int nx = std::max(1, static_cast<int>(std::lround(std::sqrt(0.5 * triangles * width / height))));
  const int ny = std::max(1, static_cast<int>(std::lround(0.5 * triangles / nx)));
  return {nx, ny};
}

TriMesh regular_rectangle(double width, double height, int triangles) {
  const auto [nx, ny] = grid_shape(width, height, triangles);
  Vec2List points;
  for (int j = 0; j <= ny; ++j) {
    for (int i = 0; i <= nx; ++i) {
      points.emplace_back(grid_coordinate(width, i, nx), grid_coordinate(height, j, ny));
    }
  }
  return flat_mesh(std::move(points), union_jack_triangles(nx, ny));
}

TriMesh irregular_rectangle(double width, double height, int triangles, uint64_t seed) {
  const double spacing = equilateral_spacing(width * height, triangles);
  const int nx = std::max(1, static_cast<int>(std::lround(width / spacing)));
  const int ny = std::max(1, static_cast<int>(std::lround(height / spacing)));
  const double hw = 0.5 * width, hh = 0.5 * height;

  ConvexDomain domain;
  for (int i = 0; i < nx; ++i) domain.boundary.emplace_back(grid_coordinate(width, i, nx), -hh);
  for (int j = 0; j < ny; ++j) domain.boundary.emplace_back(hw, grid_coordinate(height, j, ny));
  for (int i = nx; i > 0; --i) domain.boundary.emplace_back(grid_coordinate(width, i, nx), hh);
  for (int j = ny; j > 0; --j) domain.boundary.emplace_back(-hw, grid_coordinate(height, j, ny));
  domain.contains = [hw, hh](const Vec2& p, double m) {
    return std::abs(p.x()) <= hw - m && std::abs(p.y()) <= hh - m;
  };
  // A triangulation of B boundary and I interior points has 2 I + B - 2 triangles.
  const int boundary = static_cast<int>(domain.boundary.size());
  const int interior = std::max(0, (triangles - boundary + 2) / 2);
  PlanarTriangulation t = irregular_triangulation(domain, interior, spacing, seed);
  return flat_mesh(std::move(t.points), std::move(t.triangles));
}

// Triangles between two concentric rings of vertex ids (counter-clockwise from angle 0),
// advancing on whichever ring's next vertex comes first by angle.
void zip_rings(const std::vector<int>& inner, const std::vector<int>& outer, TriList& out) {
  const size_t ni = inner.size(), no = outer.size();
  size_t i = 0, o = 0;
  while (i < ni || o < no) {
    // Next angles compared exactly: (o + 1) / no <= (i + 1) / ni.
    const bool step_outer = o < no && (i == ni || (o + 1) * ni <= (i + 1) * no);
    if (step_outer) {
      out.emplace_back(inner[i % ni], outer[o], outer[(o + 1) % no]);
      ++o;
    } else {
      out.emplace_back(inner[i], outer[o % no], inner[(i + 1) % ni]);
      ++i;
    }
  }
}

// n rings with about alpha k vertices on ring k give about alpha n^2 triangles: n is chosen
// for alpha near 6 (equilateral-like), then alpha = triangles / n^2 hits the count. With an
// inner circle (inner > 0), ring k_in = round(n inner / radius) is placed on it, and the
// rings inside and outside it are spaced evenly.
TriMesh regular_disk(double radius, int triangles, double inner = 0.0) {
  const int rings = std::max(1, static_cast<int>(std::lround(std::sqrt(triangles / 6.0))));
  const double per_ring = static_cast<double>(triangles) / (rings * rings);
  const int inner_ring =
      inner > 0.0 ? std::clamp(static_cast<int>(std::lround(rings * inner / radius)), 1,
                               std::max(1, rings - 1))
                  : 0;
  auto ring_radius = [&](int k) {
    if (inner_ring == 0 || inner_ring >= rings) return radius * k / rings;
    if (k == rings) return radius;
    if (k == inner_ring) return inner;
    if (k < inner_ring) return inner * k / inner_ring;
    return inner + (radius - inner) * (k - inner_ring) / (rings - inner_ring);
  };
  Vec2List points{Vec2::Zero()};
  TriList tris;
  std::vector<int> inner_ids{0};
  for (int k = 1; k <= rings; ++k) {
    const int count = std::max(3, static_cast<int>(std::lround(per_ring * k)));
    std::vector<int> ring;
    const double r = ring_radius(k);
    for (int i = 0; i < count; ++i) {
      const double angle = 2.0 * kPi * i / count;
      ring.push_back(static_cast<int>(points.size()));
      points.emplace_back(r * std::cos(angle), r * std::sin(angle));
    }
    if (k == 1) {
      for (int i = 0; i < count; ++i) tris.emplace_back(0, ring[i], ring[(i + 1) % count]);
    } else {
      zip_rings(inner_ids, ring, tris);
    }
    inner_ids = std::move(ring);
  }
  return flat_mesh(std::move(points), std::move(tris));
}

// With an inner circle (inner > 0), its points join the boundary's as fixed points, and
// interior points keep a margin from it as from the boundary.
TriMesh irregular_disk(double radius, int triangles, uint64_t seed, double inner = 0.0) {
  const double spacing = equilateral_spacing(kPi * radius * radius, triangles);
  int count = std::max(3, static_cast<int>(std::lround(2.0 * kPi * radius / spacing)));
  if ((count - triangles) % 2 != 0) ++count;  // same parity: the count comes out exact
  ConvexDomain domain;
  for (int i = 0; i < count; ++i) {
    const double angle = 2.0 * kPi * i / count;
    domain.boundary.emplace_back(radius * std::cos(angle), radius * std::sin(angle));
  }
  const int inner_count =
      inner > 0.0 ? std::max(3, static_cast<int>(std::lround(2.0 * kPi * inner / spacing))) : 0;
  for (int i = 0; i < inner_count; ++i) {
    const double angle = 2.0 * kPi * i / inner_count;
    domain.boundary.emplace_back(inner * std::cos(angle), inner * std::sin(angle));
  }
  const double inradius = radius * std::cos(kPi / count);  // of the boundary polygon
  domain.contains = [inradius, inner, inner_count](const Vec2& p, double m) {
    const double r = p.norm();
    return r <= inradius - m && (inner_count == 0 || std::abs(r - inner) >= m);
  };
  // Every point but the `count` on the convex hull is interior to the triangulation.
  const int interior = std::max(0, (triangles - count + 2) / 2 - inner_count);
  PlanarTriangulation t = irregular_triangulation(domain, interior, spacing, seed);
  return flat_mesh(std::move(t.points), std::move(t.triangles));
}

}  // namespace

TriMesh generate_rectangle(double width, double height, int triangles, bool irregular,
                           uint64_t seed) {
  require_length("generate_rectangle", "width", width);
  require_length("generate_rectangle", "height", height);
  require_count("generate_rectangle", triangles, 2);
  return irregular ? irregular_rectangle(width, height, triangles, seed)
                   : regular_rectangle(width, height, triangles);
}

TriMesh generate_disk(double radius, int triangles, bool irregular, uint64_t seed) {
  require_length("generate_disk", "radius", radius);
  require_count("generate_disk", triangles, 6);
  return irregular ? irregular_disk(radius, triangles, seed) : regular_disk(radius, triangles);
}

TriMesh generate_disk(double radius, int triangles, bool irregular, uint64_t seed,
                      double inner_radius) {
  require_disk(radius, triangles, inner_radius);
  return irregular ? irregular_disk(radius, triangles, seed, inner_radius)
                   : regular_disk(radius, triangles, inner_radius);
}

TriMesh generate_disk(double radius, int triangles, uint64_t seed, double inner_radius,
                      const DiskGrading& grading) {
  require_disk(radius, triangles, inner_radius);
  const DiskGrading& g = grading;
  if (!(g.inner >= 0.0 && g.outer > g.inner && g.outer <= radius)) {
    throw InputError("generate_disk: the graded band must satisfy 0 <= inner < outer <= the "
                     "radius " + format_short(radius) + " m, got " + format_short(g.inner) +
                     " m to " + format_short(g.outer) + " m");
  }
  if (!(g.fine_ratio > 0.0 && g.fine_ratio <= 1.0)) {
    throw InputError("generate_disk: fine_ratio must be in (0, 1], got " +
                     format_short(g.fine_ratio));
  }
  if (!(g.transition >= 0.0 && g.transition <= radius)) {
    throw InputError("generate_disk: transition must be between 0 and the radius " +
                     format_short(radius) + " m, got " + format_short(g.transition));
  }
  Vec2List points = graded_disk_points(radius, triangles, seed, inner_radius, g);
  TriList tris = delaunay_triangles(points);
  return flat_mesh(std::move(points), std::move(tris));
}

TriMesh generate_sliver_rectangle(double width, double height, int triangles) {
  require_length("generate_sliver_rectangle", "width", width);
  require_length("generate_sliver_rectangle", "height", height);
  require_count("generate_sliver_rectangle", triangles, 96);
  auto [nx, ny] = grid_shape(width, height, triangles);
  nx = std::max(nx, 8);  // room for the thin column and three caps that do not touch it
  ny = std::max(ny, 6);

  // Column edges: every column is `step` wide except the thin one, `thin`.
  const int thin = nx / 2;
  const double step = width / (nx - 1 + kSliverWidthRatio);
  std::vector<double> xs(nx + 1);
  xs[0] = -0.5 * width;
  xs[nx] = 0.5 * width;
  for (int i = 1; i < nx; ++i) {
    xs[i] = xs[i - 1] + (i - 1 == thin ? kSliverWidthRatio * step : step);
  }
  Vec2List points;
  for (int j = 0; j <= ny; ++j) {
    for (int i = 0; i <= nx; ++i) points.emplace_back(xs[i], grid_coordinate(height, j, ny));
  }
  auto id = [nx = nx](int i, int j) { return j * (nx + 1) + i; };

  // Vertices with i + j odd have valence 4; their star is the diamond of their 4 neighbours.
  // Moving (i, j) towards the middle of the diagonal (i + 1, j)-(i, j + 1) flattens the
  // triangle between them into a cap and leaves the other triangles of the star valid.
  // Valence-4 vertices are never neighbours, so the three moves are independent.
  const int cap_columns[3] = {1, 1, nx - 1};
  const int cap_rows[3] = {1, ny - 1, ny / 2};
  for (int k = 0; k < 3; ++k) {
    const int i = cap_columns[k];
    int j = cap_rows[k];
    if ((i + j) % 2 == 0) j += (j + 1 <= ny - 1) ? 1 : -1;
    Vec2& p = points[id(i, j)];
    const Vec2 middle = 0.5 * (points[id(i + 1, j)] + points[id(i, j + 1)]);
    p += (1.0 - kCapHeightRatio) * (middle - p);
  }
  return flat_mesh(std::move(points), union_jack_triangles(nx, ny));
}

}  // namespace tissu
