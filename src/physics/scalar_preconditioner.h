// A scalar sparse Cholesky preconditioner: one unknown per vertex instead of three
// (docs/implicit.md, "Linear solves"). From the system matrix A of 3x3 vertex blocks it
// builds the V x V matrix S with S_ij = trace(A_ij) / 3 and preconditions with
// P = S^-1 (x) I3, or, block-scaled, with the 3x3 diagonal blocks D_i of A around it:
//   P = W (S'^-1 (x) I3) W,   W = diag(D_i^-1/2),   S'_ij = trace(W_i A_ij W_j) / 3,
// which keeps each vertex's own anisotropy (the barrier's stiffness along the contact
// normal, the membrane's in-plane stiffness) and leaves only the couplings scalar.
//
// S is positive definite whenever A is: S = 1/3 sum_c E_c^T A E_c, with E_c the
// (3V x V) matrix that puts a scalar field into coordinate c of every vertex, a sum of
// congruences of A (and likewise S' of W A W). The diagonal-only blocks (bending's
// second ring) are left out of the factor and their magnitudes added to the two diagonal
// entries they couple, as CholeskyPreconditioner does, which keeps it positive definite.
// The factor has a ninth of the block factor's non-zeros and costs 27 times fewer flops;
// apply() solves for the three coordinates at once. Tests:
// tests/physics/scalar_preconditioner_test.cpp and, in whole steps, tests/physics/
// implicit_test.cpp (LinearSolver.ImplicitStepsWithScalarFactorsAgreeWithCholesky).
#pragma once

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <cstdint>
#include <vector>

#include "core/types.h"
#include "physics/linear_solver.h"

namespace tissu {

class ScalarCholeskyPreconditioner : public Preconditioner {
 public:
  // Factorizes S (block_scaled false) or S' (true) of A. The additions (a constrained
  // solve's stiffness along its constrained directions) enter the diagonal blocks D_i
  // of the block-scaled variant; the plain one leaves them out (their trace would stiffen
  // the vertex in every direction). False when the factor is not positive definite.
  bool compute(const BlockSparseMatrix& A, bool block_scaled,
               const std::vector<DiagonalAddition>& additions = {});
  void apply(const Eigen::VectorXd& r, Eigen::VectorXd& z) const override;
  bool valid() const { return valid_; }

 private:
  void analyze(const BlockSparseMatrix& A);

  uint64_t pattern_id_ = 0;
  Eigen::SparseMatrix<double> lower_;  // (V x V) lower triangle of S or S', column-major
  std::vector<int> source_;            // per value of lower_: full block of A, -1 for the
                                       // unit diagonal of a vertex without a diagonal block
  struct Dropped {
    int diagonal;  // value of lower_ holding S_ii
    int block;     // diagonal-only block (i, j) of A, j != i
    int i, j;      // its vertices
  };
  std::vector<Dropped> dropped_;
  std::vector<uint8_t> solved_;        // (V) 1 = vertex in the system
  std::vector<Mat3> scale_;            // (V) W_i = D_i^-1/2 (block-scaled), else empty
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower> ldlt_;
  bool block_scaled_ = false;
  bool valid_ = false;
  mutable std::vector<Vec3> work_;     // (V) permuted right-hand sides
};

}  // namespace tissu
