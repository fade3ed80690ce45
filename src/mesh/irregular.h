// Irregular, well-shaped triangulations of convex planar regions: boundary points given by
// the caller, interior points by seeded Poisson-disk sampling, CGAL Delaunay triangulation,
// then smoothing passes that move interior points and re-triangulate.
#pragma once

#include <cstdint>
#include <functional>

#include "core/types.h"

namespace tissu {

// A convex region of the plane. All lengths in m.
struct ConvexDomain {
  Vec2List boundary;  // points on the boundary, counter-clockwise; they become mesh vertices
  // True when p is inside with at least `margin` to the boundary.
  std::function<bool(const Vec2& p, double margin)> contains;
};

struct PlanarTriangulation {
  Vec2List points;    // ordered by rows of height `spacing` (bottom to top), then by x
  TriList triangles;  // counter-clockwise
};

// Triangulates `domain` with its boundary points plus `interior_count` interior points
// (fewer only when they do not fit). `spacing` (m) is the intended edge length. With B
// boundary points the result has 2 * interior + B - 2 triangles.
PlanarTriangulation irregular_triangulation(const ConvexDomain& domain, int interior_count,
                                            double spacing, uint64_t seed);

// Delaunay triangulation of distinct points (exact predicates); triangles counter-clockwise.
TriList delaunay_triangles(const Vec2List& points);

}  // namespace tissu
