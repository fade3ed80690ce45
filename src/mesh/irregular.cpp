#include "mesh/irregular.h"

#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <utility>

#include "mesh/random.h"

namespace tissu {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using VertexBase = CGAL::Triangulation_vertex_base_with_info_2<int, Kernel>;
using DataStructure = CGAL::Triangulation_data_structure_2<VertexBase>;
using Delaunay = CGAL::Delaunay_triangulation_2<Kernel, DataStructure>;

constexpr int kCandidatesPerPoint = 30;  // Bridson's k
constexpr int kOdtPasses = 4;
constexpr int kLloydPasses = 8;

// Uniform grid over a bounding box for "is any point closer than r" queries.
class PointGrid {
 public:
  PointGrid(const Vec2& lo, const Vec2& hi, double cell)
      : lo_(lo), cell_(cell),
        nx_(std::max(1, static_cast<int>(std::ceil((hi.x() - lo.x()) / cell)) + 1)),
        ny_(std::max(1, static_cast<int>(std::ceil((hi.y() - lo.y()) / cell)) + 1)),
        head_(static_cast<size_t>(nx_) * ny_, -1) {}

  void add(const Vec2& p) {
    const size_t c = cell_of(p);
    points_.push_back(p);
    next_.push_back(head_[c]);
    head_[c] = static_cast<int>(points_.size()) - 1;
  }

  bool has_point_within(const Vec2& p, double r) const {
    const int reach = static_cast<int>(std::ceil(r / cell_));
    const int cx = column(p), cy = row(p);
    for (int y = std::max(0, cy - reach); y <= std::min(ny_ - 1, cy + reach); ++y) {
      for (int x = std::max(0, cx - reach); x <= std::min(nx_ - 1, cx + reach); ++x) {
        for (int i = head_[static_cast<size_t>(y) * nx_ + x]; i >= 0; i = next_[i]) {
          if ((points_[i] - p).squaredNorm() < r * r) return true;
        }
      }
    }
    return false;
  }

 private:
  int column(const Vec2& p) const {
    return std::clamp(static_cast<int>((p.x() - lo_.x()) / cell_), 0, nx_ - 1);
  }
  int row(const Vec2& p) const {
    return std::clamp(static_cast<int>((p.y() - lo_.y()) / cell_), 0, ny_ - 1);
  }
  size_t cell_of(const Vec2& p) const { return static_cast<size_t>(row(p)) * nx_ + column(p); }

  Vec2 lo_;
  double cell_;
  int nx_, ny_;
  std::vector<int> head_, next_;
  Vec2List points_;
};

// Bridson's Poisson-disk sampling: interior points at least r from each other and from the
// boundary points, and at least r / 2 inside the domain.
Vec2List poisson_disk(const ConvexDomain& domain, double r, PortableRandom& random) {
  Vec2 lo = domain.boundary.front(), hi = lo;
  for (const Vec2& p : domain.boundary) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const double margin = 0.5 * r;
  PointGrid grid(lo, hi, r / std::sqrt(2.0));
  for (const Vec2& p : domain.boundary) grid.add(p);

  Vec2List samples;
  for (int attempt = 0; attempt < 100 && samples.empty(); ++attempt) {
    const Vec2 p(random.uniform(lo.x(), hi.x()), random.uniform(lo.y(), hi.y()));
    if (domain.contains(p, margin) && !grid.has_point_within(p, r)) samples.push_back(p);
  }
  if (samples.empty()) return samples;
  grid.add(samples.front());

  std::vector<int> active{0};
  while (!active.empty()) {
    const size_t slot = random.below(active.size());
    const Vec2 centre = samples[active[slot]];
    bool found = false;
    for (int k = 0; k < kCandidatesPerPoint && !found; ++k) {
      // Uniform by area in the annulus r..2r around the centre.
      const double radius = r * std::sqrt(1.0 + 3.0 * random.uniform());
      const double angle = 2.0 * kPi * random.uniform();
      const Vec2 q = centre + radius * Vec2(std::cos(angle), std::sin(angle));
      if (!domain.contains(q, margin) || grid.has_point_within(q, r)) continue;
      samples.push_back(q);
      grid.add(q);
      active.push_back(static_cast<int>(samples.size()) - 1);
      found = true;
    }
    if (!found) {
      active[slot] = active.back();
      active.pop_back();
    }
  }
  return samples;
}

// Poisson-disk samples, as many as `count` when they fit: the radius is tuned until the
// sampler yields slightly more, then a random surplus is dropped (smoothing closes the gaps).
Vec2List interior_points(const ConvexDomain& domain, int count, double spacing,
                         PortableRandom& random) {
  if (count <= 0) return {};
  double r = 0.72 * spacing;
  Vec2List best;
  for (int attempt = 0; attempt < 8; ++attempt) {
    Vec2List samples = poisson_disk(domain, r, random);
    const double n = static_cast<double>(samples.size());
    if (samples.size() > best.size()) best = samples;
    if (n >= count && n <= 1.05 * count) break;
    const double ratio = n > 0 ? std::sqrt(n / (1.02 * count)) : 0.5;
    r *= std::clamp(ratio, 0.5, 1.5);
  }
  if (static_cast<int>(best.size()) <= count) return best;

  std::vector<int> order(best.size());
  std::iota(order.begin(), order.end(), 0);
  for (int i = 0; i < count; ++i) {  // partial Fisher-Yates: the first `count` are kept
    std::swap(order[i], order[i + random.below(order.size() - i)]);
  }
  order.resize(count);
  std::sort(order.begin(), order.end());
  Vec2List kept;
  kept.reserve(count);
  for (int i : order) kept.push_back(best[i]);
  return kept;
}

// Delaunay triangulation whose vertices carry the ids of `points`.
Delaunay triangulate(const Vec2List& points) {
  std::vector<std::pair<Kernel::Point_2, int>> input;
  input.reserve(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    input.emplace_back(Kernel::Point_2(points[i].x(), points[i].y()), static_cast<int>(i));
  }
  Delaunay triangulation;
  triangulation.insert(input.begin(), input.end());
  if (triangulation.number_of_vertices() != points.size()) {
    throw std::logic_error("delaunay_triangles: input has coincident points");
  }
  return triangulation;
}

Vec2 circumcentre(const Vec2& a, const Vec2& b, const Vec2& c) {
  const Vec2 ab = b - a, ac = c - a;
  const double d = 2.0 * (ab.x() * ac.y() - ab.y() * ac.x());
  const double ab2 = ab.squaredNorm(), ac2 = ac.squaredNorm();
  return a + Vec2(ac.y() * ab2 - ab.y() * ac2, ab.x() * ac2 - ac.x() * ab2) / d;
}

enum class Smoothing {
  // Optimal Delaunay triangulation (Chen & Xu): the area-weighted mean of the circumcentres
  // of the point's triangles. Converges fast from a random start.
  odt,
  // Lloyd: the centroid of the point's Voronoi cell, the polygon of those circumcentres.
  // Slower, and evens out angles and valences best.
  lloyd,
};

// Moves every interior point (id >= first_free) to its new place unless that lies closer
// than `margin` to the boundary (then it stays, which also keeps points distinct).
// Interior points are never on the convex hull, so their faces are all finite.
void smoothing_pass(Smoothing kind, const Delaunay& triangulation, const ConvexDomain& domain,
                    size_t first_free, double margin, Vec2List& points) {
  Vec2List moved = points;
  for (auto vertex : triangulation.finite_vertex_handles()) {
    const int id = vertex->info();
    if (static_cast<size_t>(id) < first_free) continue;
    Vec2 sum = Vec2::Zero();
    double weight = 0;
    Vec2 first = Vec2::Zero(), previous = Vec2::Zero();
    bool started = false;
    auto face = triangulation.incident_faces(vertex), end = face;
    do {
      const Vec2& a = points[face->vertex(0)->info()];
      const Vec2& b = points[face->vertex(1)->info()];
      const Vec2& c = points[face->vertex(2)->info()];
      const Vec2 centre = circumcentre(a, b, c);
      if (kind == Smoothing::odt) {
        const double area = (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
        sum += area * centre;
        weight += area;
      } else if (!started) {
        first = centre;
        started = true;
      } else {  // polygon centroid by the shoelace formula, relative to `first`
        const Vec2 p = previous - first, q = centre - first;
        const double cross = p.x() * q.y() - p.y() * q.x();
        sum += cross * (p + q);
        weight += 3.0 * cross;
      }
      previous = centre;
    } while (++face != end);
    if (weight > 0) {
      const Vec2 target = kind == Smoothing::odt ? Vec2(sum / weight) : Vec2(first + sum / weight);
      if (domain.contains(target, margin)) moved[id] = target;
    }
  }
  points = std::move(moved);
}

TriList triangles_of(const Delaunay& triangulation) {
  TriList triangles;
  triangles.reserve(2 * triangulation.number_of_vertices());
  for (auto face : triangulation.finite_face_handles()) {
    triangles.emplace_back(face->vertex(0)->info(), face->vertex(1)->info(),
                           face->vertex(2)->info());
  }
  return triangles;
}

// Renumbers points in rows of height `spacing`, each row by x, for memory locality; each
// triangle starts at its smallest id and the list is sorted, so the output is canonical.
PlanarTriangulation in_row_order(Vec2List points, TriList triangles, double spacing) {
  Vec2 lo = points.front();
  for (const Vec2& p : points) lo = lo.cwiseMin(p);
  std::vector<int> order(points.size());
  std::iota(order.begin(), order.end(), 0);
  auto row = [&](int i) { return std::floor((points[i].y() - lo.y()) / spacing); };
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    if (row(a) != row(b)) return row(a) < row(b);
    if (points[a].x() != points[b].x()) return points[a].x() < points[b].x();
    return points[a].y() < points[b].y();
  });
  std::vector<int> new_id(points.size());
  PlanarTriangulation out;
  for (size_t k = 0; k < order.size(); ++k) {
    new_id[order[k]] = static_cast<int>(k);
    out.points.push_back(points[order[k]]);
  }
  for (Tri& t : triangles) {
    t = Tri(new_id[t[0]], new_id[t[1]], new_id[t[2]]);
    while (t[0] > t[1] || t[0] > t[2]) t = Tri(t[1], t[2], t[0]);  // rotation keeps CCW
  }
  std::sort(triangles.begin(), triangles.end(), [](const Tri& a, const Tri& b) {
    return std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3);
  });
  out.triangles = std::move(triangles);
  return out;
}

}  // namespace

TriList delaunay_triangles(const Vec2List& points) { return triangles_of(triangulate(points)); }

PlanarTriangulation irregular_triangulation(const ConvexDomain& domain, int interior_count,
                                            double spacing, uint64_t seed) {
  PortableRandom random(seed);
  Vec2List points = domain.boundary;
  const size_t first_free = points.size();
  for (const Vec2& p : interior_points(domain, interior_count, spacing, random)) {
    points.push_back(p);
  }
  const double margin = 0.25 * spacing;
  for (int pass = 0; pass < kOdtPasses + kLloydPasses; ++pass) {
    const Smoothing kind = pass < kOdtPasses ? Smoothing::odt : Smoothing::lloyd;
    smoothing_pass(kind, triangulate(points), domain, first_free, margin, points);
  }
  return in_row_order(points, delaunay_triangles(points), spacing);
}

}  // namespace tissu
