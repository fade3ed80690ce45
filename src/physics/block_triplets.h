// Accumulator for sparse 3V x 3V Jacobians built from 3x3 vertex blocks
// (df_i/dx_j, df_i/dv_j). Turned into an Eigen sparse matrix by the implicit solver.
#pragma once

#include <Eigen/Sparse>
#include <vector>

#include "core/types.h"

namespace tissu {

struct BlockTriplets {
  std::vector<Eigen::Triplet<double>> entries;

  // Adds `block` at rows 3*row_vertex.., columns 3*col_vertex...
  void add(int row_vertex, int col_vertex, const Mat3& block) {
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) {
        entries.emplace_back(3 * row_vertex + r, 3 * col_vertex + c, block(r, c));
      }
    }
  }
  void clear() { entries.clear(); }
};

}  // namespace tissu
