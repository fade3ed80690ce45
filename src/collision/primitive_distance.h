// Closest points between the primitives of triangle meshes: a point and a triangle, two
// segments. Positions in m. The algorithms follow Ericson, "Real-Time Collision Detection"
// (2005), 5.1.5 (point-triangle, by Voronoi regions) and 5.1.9 (segment-segment).
// Tested against brute-force sampling in tests/collision/primitive_distance_test.
#pragma once

#include "core/types.h"

namespace tissu {

// The part of a triangle (a, b, c) a closest point lies on.
enum class TriangleFeature { Face, EdgeAB, EdgeBC, EdgeCA, VertexA, VertexB, VertexC };

struct TrianglePoint {
  Vec3 point;                      // closest point on the triangle, m
  Vec3 weights;                    // its barycentric coordinates (w_a, w_b, w_c), sum 1
  TriangleFeature feature = TriangleFeature::Face;
};

// The point of triangle (a, b, c) closest to p. A degenerate triangle (collinear corners)
// is handled as the segment or point it collapses to.
TrianglePoint closest_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

struct SegmentPoints {
  double s = 0.0;  // closest point on the first segment: p0 + s (p1 - p0), s in [0, 1]
  double t = 0.0;  // closest point on the second: q0 + t (q1 - q0), t in [0, 1]
  double distance2 = 0.0;  // squared distance between them, m^2
};

// The closest points of segments [p0, p1] and [q0, q1] (parallel and degenerate segments
// included: then one of the closest pairs).
SegmentPoints closest_between_segments(const Vec3& p0, const Vec3& p1, const Vec3& q0,
                                       const Vec3& q1);

}  // namespace tissu
