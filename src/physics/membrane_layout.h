// The membrane's rest data in the layout of the vectorised kernel (membrane_simd.h):
// structure of arrays, one entry per triangle, so that lane l of a vector holds triangle
// t + l. Built once by precompute_rest; never changes during a run.
#pragma once

#include <cstdint>
#include <vector>

#include "core/types.h"

namespace tissu {

struct TriangleRest;  // physics/model.h

struct MembraneLayout {
  // Entries past the last triangle that a full vector may read: zero factors, vertex 0.
  static constexpr int kPadding = 16;
  int num_triangles = 0;
  uint64_t mesh_id = 0;  // Model::mesh_id it was built for
  // (T + kPadding) each: r_u and r_v of the corners a, b, c (1/m), rest area (m^2).
  std::vector<double> ru0, ru1, ru2, rv0, rv1, rv2, area;
  // (T + kPadding) each: 3 x vertex id of the corners, the offset of the vertex's x
  // coordinate in a Vec3List seen as doubles.
  std::vector<int32_t> a, b, c;

  // Bytes of rest data the kernel reads per triangle.
  static constexpr int kBytesPerTriangle = 7 * sizeof(double) + 3 * sizeof(int32_t);
};

// The layout of `triangles` with rest data `rest`.
MembraneLayout build_membrane_layout(const TriList& triangles,
                                     const std::vector<TriangleRest>& rest, uint64_t mesh_id);

}  // namespace tissu
