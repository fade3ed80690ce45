// Sparse linear algebra of the implicit integrators (docs/implicit.md): a matrix of 3x3
// vertex blocks in compressed-row form whose pattern is built once and refilled every
// Newton iteration, the block-Jacobi (3x3 per vertex) preconditioner and a preconditioned
// conjugate-gradient loop.
//
// Vectors are flat (3V): entry 3 i + c is coordinate c of vertex i. Vertices without a
// diagonal block (pinned vertices, removed from the solve) have empty rows and columns;
// the solver keeps their entries at zero.
#pragma once

#include <Eigen/Core>
#include <Eigen/CholmodSupport>
#include <Eigen/SparseCore>
#include <cstdint>
#include <utility>
#include <vector>

#include "core/types.h"

namespace tissu {

// Matrix of V x V blocks of 3x3 in compressed rows. Two kinds of blocks: full 3x3 blocks
// (stored column-major, 9 doubles) and diagonal-only blocks (3 doubles: the entries
// (0,0), (1,1), (2,2)), the latter for vertex pairs that only couple each coordinate with
// itself (the bending Jacobian's second-ring neighbours), so that a matrix-vector product
// reads less memory. All values live in one array: the full blocks first, then the
// diagonal-only ones. (Storing only the upper block triangle of the symmetric system
// halves the memory too, but its scattered updates made the product 30% slower.)
class BlockSparseMatrix {
 public:
  // Pattern from the (row vertex, column vertex) pairs of the full and of the
  // diagonal-only blocks; duplicates are merged, a pair in both lists is full. Every
  // diagonal (i, i) pair should be full. Values are zero afterwards.
  void set_pattern(int num_vertices, std::vector<std::pair<int, int>> full,
                   std::vector<std::pair<int, int>> diagonal_only = {});

  int num_vertices() const { return num_vertices_; }
  // Changes with every set_pattern (unique across matrices): lets caches of the pattern
  // (CholeskyPreconditioner's ordering) know when to rebuild.
  uint64_t pattern_id() const { return pattern_id_; }
  // Full blocks of vertex row i: indices row_begin(i) .. row_end(i) - 1, columns block_column.
  int row_begin(int i) const { return row_start_[i]; }
  int row_end(int i) const { return row_start_[i + 1]; }
  int block_column(int b) const { return col_[b]; }
  // Diagonal-only blocks of row i, their columns, and the index of their first value.
  int diagonal_only_begin(int i) const { return drow_start_[i]; }
  int diagonal_only_end(int i) const { return drow_start_[i + 1]; }
  int diagonal_only_column(int d) const { return dcol_[d]; }
  size_t diagonal_only_value(int d) const { return 9 * col_.size() + 3 * static_cast<size_t>(d); }
  int num_blocks() const { return static_cast<int>(col_.size()); }
  int num_diagonal_blocks() const { return static_cast<int>(dcol_.size()); }

  // Index of entry (r, c) (0..2) of block (i, j) in values(), -1 when it is not stored
  // (the pair is absent, or diagonal-only and r != c).
  int find_entry(int i, int j, int r, int c) const;
  // Index of full block (i, j) (its values at 9 * index), -1 when absent.
  int find(int i, int j) const;
  // Index of the full diagonal block of vertex i, -1 when absent.
  int diagonal(int i) const { return diag_[i]; }

  void set_zero();
  double* block_values(int b) { return values_.data() + 9 * static_cast<size_t>(b); }
  const double* block_values(int b) const { return values_.data() + 9 * static_cast<size_t>(b); }
  std::vector<double>& values() { return values_; }
  const std::vector<double>& values() const { return values_; }

  // y = A x (3V vectors), its rows shared among at most `threads` threads (the same bits on
  // any count).
  void multiply(const Eigen::VectorXd& x, Eigen::VectorXd& y, int threads = 1) const;

  // Dense copy, for tests on small matrices.
  Eigen::MatrixXd to_dense() const;

 private:
  static constexpr int kRowsPerItem = 256;  // vertex rows per item of a threaded product
  void multiply_rows(const Eigen::VectorXd& x, Eigen::VectorXd& y, int first, int end) const;

  int num_vertices_ = 0;
  uint64_t pattern_id_ = 0;
  std::vector<int> row_start_;   // (V+1) first full block of each row
  std::vector<int> col_;         // (full blocks) column vertex, sorted within a row
  std::vector<int> drow_start_;  // (V+1) first diagonal-only block of each row
  std::vector<int> dcol_;        // (diagonal-only blocks) column vertex, sorted in a row
  std::vector<int> diag_;        // (V) diagonal block index or -1
  std::vector<double> values_;   // 9 per full block, then 3 per diagonal-only block
};

// Square column-major m with the compressed columns given (outer: n + 1 starts, inner: the
// rows of each column in order); every value 1.
void set_compressed_columns(Eigen::SparseMatrix<double>& m,
                            const std::vector<Eigen::SparseMatrix<double>::StorageIndex>& outer,
                            const std::vector<Eigen::SparseMatrix<double>::StorageIndex>& inner);

// z = P r for a symmetric positive definite approximation P of A^-1.
class Preconditioner {
 public:
  virtual ~Preconditioner() = default;
  virtual void apply(const Eigen::VectorXd& r, Eigen::VectorXd& z) const = 0;
};

// Block Jacobi: P = inverse of the 3x3 diagonal blocks of A. Vertices whose diagonal block
// is absent get z = 0; a block that is not positive definite (cannot happen for
// M - h df/dv - h^2 df/dx with the projected stiffness) falls back to scalar Jacobi.
class BlockJacobiPreconditioner : public Preconditioner {
 public:
  void compute(const BlockSparseMatrix& A);
  void apply(const Eigen::VectorXd& r, Eigen::VectorXd& z) const override;

 private:
  std::vector<Mat3> inverse_;  // (V)
};

// Terms of a system matrix that its block pattern does not hold (couplings between
// vertices that share no triangle), applied by product: add_product adds E x to y (3V).
class MatrixAddition {
 public:
  virtual ~MatrixAddition() = default;
  virtual void add_product(const Eigen::VectorXd& x, Eigen::VectorXd& y) const = 0;
};

// A block outside the pattern of a symmetric matrix: E(row, column) += block and
// E(column, row) += block^T, row < column (vertex ids).
struct OffPatternBlock {
  int row = 0;
  int column = 0;
  Mat3 block = Mat3::Zero();
};

// A MatrixAddition made of such blocks.
class OffPatternBlocks : public MatrixAddition {
 public:
  void clear() { blocks_.clear(); }
  bool empty() const { return blocks_.empty(); }
  // Adds `block` at (i, j) and its transpose at (j, i), i != j.
  void add(int i, int j, const Mat3& block);
  const std::vector<OffPatternBlock>& blocks() const { return blocks_; }
  void add_product(const Eigen::VectorXd& x, Eigen::VectorXd& y) const override;

 private:
  std::vector<OffPatternBlock> blocks_;
};

// Sparse Cholesky factor (CHOLMOD, supernodal) of A with its diagonal-only blocks (the
// bending Jacobian's second-ring couplings) dropped and their magnitudes added to the
// diagonal: the factored matrix is A + sum over dropped pairs of [|a| -a; -a |a|] >= A, so
// it stays positive definite, and it fills in about a third as much (5000 triangles: 47
// instead of 458 Mflop per factorization). Without bending it is A itself and PCG converges
// in one iteration; with bending in a few. Ordering and symbolic analysis are done once per
// pattern, the numeric factorization on every compute(). Vertices without a diagonal
// block get z = 0.
// A 3x3 block added to a vertex's diagonal block before factorizing.
struct DiagonalAddition {
  int vertex = -1;
  Mat3 block = Mat3::Zero();
};

class CholeskyPreconditioner : public Preconditioner {
 public:
  // Factorizes A plus the given diagonal additions (for a constrained solve: a large
  // stiffness along each constrained direction, so that the factor approximates the inverse
  // of the filtered system). False when that is not positive definite (the factor is then
  // unusable).
  // With `off_pattern`, the factor is of A plus those blocks: its pattern is A's with
  // every off-pattern block's vertex pair added; it is analysed again when a block falls
  // outside the pairs of the last analysis (which then takes those pairs and the new ones,
  // or the new ones alone once the old outnumber them twice over).
  // With `diagonal_shift` > 0 each vertex's diagonal block D is factored as D +
  // diagonal_shift (D - lambda_min(D) I): heavier along its stiff directions only. A retry
  // for a factor that rounding left short of positive definite, where barrier stiffnesses
  // many orders of magnitude beyond the masses swamp them.
  bool compute(const BlockSparseMatrix& A, const std::vector<DiagonalAddition>& additions = {},
               const std::vector<OffPatternBlock>* off_pattern = nullptr,
               double diagonal_shift = 0.0);
  // Analyses done (ordering and symbolic factorization).
  int analyses() const { return analyses_; }
  void apply(const Eigen::VectorXd& r, Eigen::VectorXd& z) const override;
  bool valid() const { return valid_; }
  // Pattern of the matrix last factorized (BlockSparseMatrix::pattern_id).
  uint64_t pattern_id() const { return pattern_id_; }

 private:
  void analyze(const BlockSparseMatrix& A);
  // Whether every block's vertex pair is among the analysed extra pairs; fills
  // extra_values_ if so.
  bool gather_off_pattern(const std::vector<OffPatternBlock>& blocks);

  uint64_t pattern_id_ = 0;
  int analyses_ = 0;
  Eigen::SparseMatrix<double> lower_;  // lower triangle of A (column-major)
  std::vector<int64_t> source_;        // per stored value of lower_: index in A.values(),
                                       // -1 for the unit diagonal of a row without block,
                                       // -2 - k for extra_values_[k]
  std::vector<std::pair<int, int>> extra_pairs_;  // (row < column) added to A's pattern, sorted
  std::vector<double> extra_values_;   // 9 per extra pair, its block column-major
  std::vector<std::pair<int64_t, int64_t>> dropped_;  // (diagonal value of lower_, dropped
                                                      // entry's index in A.values())
  std::vector<uint8_t> solved_;        // (3V) 1 = coordinate in the system
  std::vector<int64_t> diagonal_block_;  // (9V) value of lower_ holding entry (r, c), r >= c,
                                         // of vertex i's diagonal block at 9 i + 3 c + r
  Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Lower> llt_;
  bool valid_ = false;
};

struct CgResult {
  int iterations = 0;
  double relative_residual = 0.0;  // |b - A x| / |b| at exit (recursive residual)
  bool converged = false;
  bool breakdown = false;  // p^T A p <= 0: the matrix is not positive definite
};

// Scratch vectors of the conjugate-gradient loop (kept to avoid allocation per solve).
struct CgWorkspace {
  Eigen::VectorXd r, z, p, Ap;
  Eigen::VectorXd best_x;  // the iterate with the smallest residual so far
  int threads = 1;  // for the matrix-vector products
};

// The directions a constrained solve keeps fixed: apply() zeroes them in a 3V vector (an
// orthogonal projection S, per vertex).
class SolveFilter {
 public:
  virtual ~SolveFilter() = default;
  virtual void apply(Eigen::VectorXd& y) const = 0;
};

// Preconditioned conjugate gradients for symmetric positive definite A: solves A x = b to
// |b - A x|_W <= tolerance |b|_W, starting from the x given (e.g. zero or a warm start),
// where |y|_W^2 = sum_k w_k y_k^2 with the weights w (3V) when given, else the 2-norm.
// Stops after max_iterations. With a filter S it solves S A S x = S b for x = S x in the
// range of S (the prefiltered PCG of Tamstorf, Jones & McCormick 2015, with homogeneous
// constraints): the filtered directions of x stay zero, and the residual is measured on
// the others. With an addition E the matrix is A + E (A + E symmetric positive definite).
CgResult solve_pcg(const BlockSparseMatrix& A, const Preconditioner& P, const Eigen::VectorXd& b,
                   double tolerance, int max_iterations, Eigen::VectorXd& x, CgWorkspace& work,
                   const Eigen::VectorXd* weights = nullptr, const SolveFilter* filter = nullptr,
                   const MatrixAddition* addition = nullptr);

}  // namespace tissu
