// The bending term's constant per-triangle data (bending.h, docs/bending.md): for each
// triangle of the flat rest sheet, weights that turn vertex positions into the second
// derivatives x_uu, x_vv, x_uv. Built once from the rest coordinates: a quadratic patch
// per triangle through its corners and hinge apices (nearby vertices at boundaries and
// for ill-posed apices, a least-squares fit for needles and caps), the mean patch
// gradient at each edge's midpoint, and each triangle's Hessian as the flux of its edges'
// gradients. The bending force only reads the result.
#pragma once

#include <cstdint>
#include <vector>

#include "core/types.h"

namespace tissu {

// Second-derivative stencil of one triangle: d^2x/du^2 at the triangle is approximated by
// sum_j w_uu[j] x[vertex[j]] (exact when x is a quadratic function of (u, v), zero when it
// is affine); the same for vv and uv.
struct BendingStencil {
  std::vector<int> vertex;    // vertex ids
  std::vector<double> w_uu;   // 1/m^2, one per vertex
  std::vector<double> w_vv;   // 1/m^2
  std::vector<double> w_uv;   // 1/m^2
  double area = 0.0;          // rest area of the triangle, m^2
};

// The stencils of a sheet and how they were built.
struct BendingStencils {
  std::vector<BendingStencil> stencils;  // (T) one per triangle

  // Diagnostics of the precomputation.
  // Triangles with fewer than 3 distinct hinge apices (a boundary or non-manifold edge, or
  // a corner of valence 3): the missing extra vertices were chosen nearby.
  int boundary_stencils = 0;
  // Interior triangles whose hinge apices were ill-conditioned (nearly on one conic with
  // the corners): a better-conditioned set of nearby vertices containing one apex was used.
  int fallback_stencils = 0;
  // Needle or cap triangles whose interpolating patch still had large weights: a
  // least-squares quadratic over up to 12 nearby vertices was used instead.
  int least_squares_stencils = 0;
  // Triangles whose Hessian is their own patch's rather than the flux of the edge
  // gradients: least-squares stencils and caps (see docs/bending.md).
  int patch_hessians = 0;
  // Triangles whose three corners are pinned: held rigid by a clamp, no bending energy.
  int clamped_triangles = 0;
  double max_amplification = 0.0;  // max over triangles of |w|_F l^2 (l^2: mean squared edge)
};

// Builds the stencils of the flat rest sheet with coordinates `rest_uv` (m); triangles
// whose three corners are `pinned` are clamped (an empty stencil). Throws InputError for
// a vertex id out of range or a degenerate rest triangle.
BendingStencils build_bending_stencils(const TriList& triangles, const Vec2List& rest_uv,
                                       const std::vector<uint8_t>& pinned);

}  // namespace tissu
