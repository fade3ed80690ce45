#include "collision/crossings.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/intersections.h>

#include <algorithm>

#include "collision/bvh.h"

namespace tissu {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Segment = Kernel::Segment_3;
using Triangle = Kernel::Triangle_3;

Point point(const Vec3& p) { return Point(p.x(), p.y(), p.z()); }

// A triangle as the point set it is: a triangle, or when its corners are collinear the
// segment between its two farthest corners, or a point. CGAL's triangle predicates need
// non-degenerate triangles.
struct Shape {
  Point p[3];
  int n = 3;  // 3 triangle, 2 segment, 1 point
};

Shape shape_of(const Vec3& a, const Vec3& b, const Vec3& c) {
  Shape s{{point(a), point(b), point(c)}, 3};
  if (!CGAL::collinear(s.p[0], s.p[1], s.p[2])) return s;
  // Collinear: the extreme pair along the line spans the set.
  int lo = 0, hi = 0;
  for (int k = 1; k < 3; ++k) {
    if (CGAL::compare_xyz(s.p[k], s.p[lo]) == CGAL::SMALLER) lo = k;
    if (CGAL::compare_xyz(s.p[k], s.p[hi]) == CGAL::LARGER) hi = k;
  }
  const Point first = s.p[lo], second = s.p[hi];
  s.p[0] = first;
  s.p[1] = second;
  s.n = first == second ? 1 : 2;
  return s;
}

bool is_degenerate(const Vec3List& x, const Tri& t) {
  return CGAL::collinear(point(x[t[0]]), point(x[t[1]]), point(x[t[2]]));
}

// Exact intersection test of two shapes.
bool shapes_meet(const Shape& a, const Shape& b) {
  if (a.n < b.n) return shapes_meet(b, a);
  if (a.n == 3) {
    const Triangle t(a.p[0], a.p[1], a.p[2]);
    if (b.n == 3) return CGAL::do_intersect(t, Triangle(b.p[0], b.p[1], b.p[2]));
    if (b.n == 2) return CGAL::do_intersect(Segment(b.p[0], b.p[1]), t);
    return t.has_on(b.p[0]);
  }
  if (a.n == 2) {
    const Segment s(a.p[0], a.p[1]);
    if (b.n == 2) return CGAL::do_intersect(s, Segment(b.p[0], b.p[1]));
    return s.has_on(b.p[0]);
  }
  return a.p[0] == b.p[0];
}

// Boxes of the triangles: min/max of exact coordinates, so overlap tests are exact too.
std::vector<Box3> triangle_boxes(const Vec3List& x, const TriList& triangles) {
  std::vector<Box3> boxes(triangles.size());
  for (size_t t = 0; t < triangles.size(); ++t) {
    Box3 box(x[triangles[t][0]]);
    box.extend(x[triangles[t][1]]);
    box.extend(x[triangles[t][2]]);
    boxes[t] = box;
  }
  return boxes;
}

// Does segment a->b meet the triangle (a, d, e) anywhere but at a? Only when b lies in the
// plane of the triangle and inside its corner at a (closed).
bool edge_enters_corner(const Point& a, const Point& b, const Point& d, const Point& e) {
  if (CGAL::orientation(a, d, e, b) != CGAL::COPLANAR) return false;
  return CGAL::coplanar_orientation(a, d, e, b) != CGAL::NEGATIVE &&
         CGAL::coplanar_orientation(a, e, d, b) != CGAL::NEGATIVE;
}

// Triangles (a, b, c) and (a, d, e) sharing only vertex a: do they meet elsewhere?
bool meet_beyond_vertex(const Point& a, const Point& b, const Point& c, const Point& d,
                        const Point& e) {
  const Triangle t1(a, b, c), t2(a, d, e);
  return CGAL::do_intersect(Segment(b, c), t2) || CGAL::do_intersect(Segment(d, e), t1) ||
         edge_enters_corner(a, b, d, e) || edge_enters_corner(a, c, d, e) ||
         edge_enters_corner(a, d, b, c) || edge_enters_corner(a, e, b, c);
}

// Triangles (a, b, c) and (a, b, d) sharing edge ab: folded flat onto each other?
bool meet_beyond_edge(const Point& a, const Point& b, const Point& c, const Point& d) {
  if (CGAL::orientation(a, b, c, d) != CGAL::COPLANAR) return false;
  return CGAL::coplanar_orientation(a, b, c, d) != CGAL::NEGATIVE;
}

// Two triangles of the same mesh, by the vertices they share. A zero-area triangle that
// shares a vertex with the other counts as crossing it (the cloth has collapsed there).
bool triangles_cross(const Vec3List& x, const Tri& s, const Tri& t) {
  int shared_s[3], shared_t[3], n = 0;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      if (s[i] == t[j]) {
        shared_s[n] = i;
        shared_t[n] = j;
        ++n;
      }
    }
  }
  if (n == 0) {
    return shapes_meet(shape_of(x[s[0]], x[s[1]], x[s[2]]), shape_of(x[t[0]], x[t[1]], x[t[2]]));
  }
  if (n < 3 && (is_degenerate(x, s) || is_degenerate(x, t))) return true;
  if (n == 1) {
    const int i = shared_s[0], j = shared_t[0];
    return meet_beyond_vertex(point(x[s[i]]), point(x[s[(i + 1) % 3]]),
                              point(x[s[(i + 2) % 3]]), point(x[t[(j + 1) % 3]]),
                              point(x[t[(j + 2) % 3]]));
  }
  if (n == 2) {
    const int other_s = 3 - shared_s[0] - shared_s[1];
    const int other_t = 3 - shared_t[0] - shared_t[1];
    return meet_beyond_edge(point(x[s[shared_s[0]]]), point(x[s[shared_s[1]]]),
                            point(x[s[other_s]]), point(x[t[other_t]]));
  }
  return false;  // the same three vertices: one triangle listed twice
}

void sort_and_cut(std::vector<TrianglePair>& pairs, std::size_t limit) {
  std::sort(pairs.begin(), pairs.end(), [](const TrianglePair& a, const TrianglePair& b) {
    return a.first < b.first || (a.first == b.first && a.second < b.second);
  });
  if (pairs.size() > limit) pairs.resize(limit);
}

}  // namespace

CrossingReport self_crossings(const Vec3List& x, const TriList& triangles, std::size_t limit) {
  CrossingReport report;
  if (limit == 0) return report;
  Bvh tree;
  tree.build(triangle_boxes(x, triangles));
  tree.for_each_self_overlap([&](int i, int j) {
    if (report.pairs.size() >= limit) return;
    if (triangles_cross(x, triangles[i], triangles[j])) {
      report.pairs.push_back({std::min(i, j), std::max(i, j)});
    }
  });
  sort_and_cut(report.pairs, limit);
  report.count = report.pairs.size();
  return report;
}

CrossingReport crossings_between(const Vec3List& xa, const TriList& ta, const Vec3List& xb,
                                 const TriList& tb, std::size_t limit) {
  CrossingReport report;
  if (limit == 0) return report;
  Bvh a, b;
  a.build(triangle_boxes(xa, ta));
  b.build(triangle_boxes(xb, tb));
  a.for_each_overlap_with(b, [&](int i, int j) {
    if (report.pairs.size() >= limit) return;
    const Tri &s = ta[i], &t = tb[j];
    if (shapes_meet(shape_of(xa[s[0]], xa[s[1]], xa[s[2]]),
                    shape_of(xb[t[0]], xb[t[1]], xb[t[2]]))) {
      report.pairs.push_back({i, j});
    }
  });
  sort_and_cut(report.pairs, limit);
  report.count = report.pairs.size();
  return report;
}

}  // namespace tissu
