// The matrix of an implicit step, A = M - beta df/dv - beta^2 df/dx over the free vertices
// (docs/implicit.md), written straight from the force terms into a BlockSparseMatrix:
// - its block pattern is planned once from the mesh (every vertex pair of a triangle, the
//   diagonal) and the bending stencils (diagonal-only blocks), pinned rows and columns left
//   out;
// - each triangle's nine blocks go to slots found once, so the membrane and the wind add
//   their blocks without a search or a sort;
// - the parts that do not change during a run (masses, bending, air damping) are summed
//   once per beta and copied in before the triangle terms are added.
#pragma once

#include <cstdint>
#include <vector>

#include "physics/force_term.h"
#include "physics/linear_solver.h"
#include "physics/model.h"

namespace tissu {

class SystemMatrix {
 public:
  // Plans the pattern and slots for `model` unless already planned for its mesh and pins.
  void plan(const Model& model);

  // A at (x, v, t) for `beta` (s); with `project_psd` the solver's symmetric positive
  // definite approximation of the Jacobian (add_force_jacobian). On several threads the
  // triangles' blocks are computed in parallel, then each block of A adds them in triangle
  // order: the same bits on any thread count.
  void assemble(const Model& model, const Vec3List& x, const Vec3List& v, double t, double beta,
                bool project_psd, int threads = 1);

  // Adds `block` to the diagonal block of free vertex i of the assembled matrix.
  void add_diagonal(int i, const Mat3& block);
  // Adds `block` to block (i, j) of free vertices i and j of one triangle.
  void add_block(int i, int j, const Mat3& block);
  // Adds `block` to block (i, j) if the pattern holds it; false (nothing added) if not.
  bool add_block_if_held(int i, int j, const Mat3& block);

  const BlockSparseMatrix& matrix() const { return A_; }

 private:
  friend class SlotSink;
  // Adds the model's constant terms (mass, bending, air damping) for beta into values.
  void add_constant_terms(const Model& model, double beta, std::vector<double>& values) const;
  // Adds the membrane's blocks to A_, computed on `threads` threads.
  void add_membrane_blocks(const Model& model, const Vec3List& x, const Vec3List& v,
                           double beta, bool project_psd, int threads);

  BlockSparseMatrix A_;
  // Per triangle, its nine block slots (corner a row, corner b column at 3 a + b): the
  // index of the full block in A_, or -1 where a corner is pinned.
  std::vector<int> triangle_slots_;
  // Per full block of A_, what the triangles add to it in triangle order: indices of their
  // blocks in triangle_blocks_ (81 t + 9 k), block b's at
  // [slot_sources_start_[b], slot_sources_start_[b + 1]).
  std::vector<int> slot_sources_start_;
  std::vector<int64_t> slot_sources_;
  std::vector<double> triangle_blocks_;  // (81 T) the triangles' blocks of one assembly
  std::vector<double> constant_values_;  // the constant terms for constant_beta_
  double constant_beta_ = -1.0;
  uint64_t planned_mesh_ = 0;
  std::vector<uint8_t> planned_pins_;
  bool planned_bending_ = false;
};

}  // namespace tissu
