// Sparse 3V x 3V Jacobians collected as 3x3 vertex blocks (df_i/dx_j, df_i/dv_j), for tests
// and checks; the implicit solver writes its system matrix directly instead.
#pragma once

#include <Eigen/Sparse>
#include <vector>

#include "core/types.h"
#include "physics/force_term.h"

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
  // The sum of the entries as a (3 num_vertices)^2 sparse matrix.
  Eigen::SparseMatrix<double> to_sparse(int num_vertices) const {
    Eigen::SparseMatrix<double> m(3 * num_vertices, 3 * num_vertices);
    m.setFromTriplets(entries.begin(), entries.end());
    return m;
  }
};

// A JacobianSink that collects the weighted blocks it receives as triplets.
class TripletSink : public JacobianSink {
 public:
  TripletSink(double cx, double cv, BlockTriplets& out) : JacobianSink(cx, cv), out_(out) {}
  void add_triangle(int, const Tri& tri, const Mat3* blocks) override {
    for (int a = 0; a < 3; ++a) {
      for (int b = 0; b < 3; ++b) out_.add(tri[a], tri[b], blocks[3 * a + b]);
    }
  }
  void add(int i, int j, const Mat3& block) override { out_.add(i, j, block); }

 private:
  BlockTriplets& out_;
};

}  // namespace tissu
