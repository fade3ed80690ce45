// Flat cloth meshes made from parameters. Every generated mesh lies in the x-y plane (z = 0)
// centred at the origin, with rest_uv = (x, y) in m and triangles counter-clockwise in (u, v).
// Bad parameters raise InputError.
#pragma once

#include <cstdint>

#include "mesh/mesh.h"

namespace tissu {

// A width x height rectangle (m) with about `triangles` triangles (within a few percent
// when each side gets several cells).
// Regular: nx x ny cells matched to the aspect ratio, each cut in two along a diagonal that
// alternates from cell to cell (a "union jack" pattern, no preferred shear direction).
// Irregular: boundary points evenly spaced on the edges, seeded Poisson-disk interior points,
// Delaunay triangulation and optimal-Delaunay smoothing; the same seed gives the same mesh.
TriMesh generate_rectangle(double width, double height, int triangles, bool irregular,
                           uint64_t seed);

// A disk of `radius` (m). Regular: n equally spaced concentric rings around a centre vertex,
// ring k with about 6k vertices (exactly 6k when the count is 6 n^2), zipped together. Irregular: as for the rectangle, with boundary points evenly
// spaced on the circle. The covered area is that of the boundary polygon, slightly below pi r^2.
TriMesh generate_disk(double radius, int triangles, bool irregular, uint64_t seed);

// The same disk with vertices on a concentric circle of `inner_radius` (0 < inner_radius <
// radius), so that a centre disc can be clamped along an exact circle, as Cusick's drape
// test clamps its fabric. Regular: the rings are spaced evenly inside and outside that
// circle, which is one of them. Irregular: its points, evenly spaced, stay where they are
// as the boundary's do. The count of triangles is kept as without the inner circle.
TriMesh generate_disk(double radius, int triangles, bool irregular, uint64_t seed,
                      double inner_radius);

// A band of a disk meshed finer: edges `fine_ratio` times those elsewhere at distances
// `inner`..`outer` (m) from the centre, changing linearly in the distance over
// `transition` (m) on either side of the band.
struct DiskGrading {
  double inner = 0.0;       // m
  double outer = 0.0;       // m, above inner
  double fine_ratio = 1.0;  // in (0, 1]
  double transition = 0.0;  // m, >= 0
};

// The disk with a circle of vertices at `inner_radius` as above, graded by `grading`:
// concentric rings of vertices spaced by the local edge (sqrt(3)/2 of it apart, 2 pi r /
// edge vertices on a ring of radius r), each ring turned by a seeded random angle, and
// their Delaunay triangulation. The edge elsewhere is chosen for about `triangles`
// triangles (within 1% for Cusick's band, 3% for a band reaching the rim). Used for
// Cusick's drape (docs/bending.md).
TriMesh generate_disk(double radius, int triangles, uint64_t seed, double inner_radius,
                      const DiskGrading& grading);

// Degenerate shapes for stability tests, cut into a regular (union jack) rectangle mesh.
constexpr double kSliverWidthRatio = 0.01;  // the thin column's width / a normal column's
constexpr double kCapHeightRatio = 1e-3;    // a cap's area / its area in the regular grid
// The middle column of cells is kSliverWidthRatio as wide as the others, so its triangles
// have edges in the ratio 1:100 (needles). Three interior vertices of valence 4 are pushed
// almost onto the diagonal opposite them, leaving "caps": triangles with an angle near 180
// degrees and kCapHeightRatio of their normal area (near zero). Needs at least 96 triangles.
TriMesh generate_sliver_rectangle(double width, double height, int triangles);

}  // namespace tissu
