#include "physics/scalar_preconditioner.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

namespace tissu {

void ScalarCholeskyPreconditioner::analyze(const BlockSparseMatrix& A) {
  const int n = A.num_vertices();
  using StorageIndex = Eigen::SparseMatrix<double>::StorageIndex;
  std::vector<StorageIndex> outer(n + 1, 0), inner;
  source_.clear();
  dropped_.clear();
  solved_.assign(n, 0);
  // Column i of the lower triangle is row i of the upper one: the full blocks (i, j),
  // j >= i, in A's row order (sorted, the diagonal block first).
  for (int i = 0; i < n; ++i) {
    if (A.diagonal(i) >= 0) {
      solved_[i] = 1;
      const int diagonal = static_cast<int>(inner.size());
      for (int b = A.row_begin(i); b < A.row_end(i); ++b) {
        if (A.block_column(b) < i) continue;
        inner.push_back(A.block_column(b));
        source_.push_back(b);
      }
      for (int d = A.diagonal_only_begin(i); d < A.diagonal_only_end(i); ++d) {
        const int j = A.diagonal_only_column(d);
        if (j != i) dropped_.push_back({diagonal, d, i, j});
      }
    } else {
      inner.push_back(i);
      source_.push_back(-1);
    }
    outer[i + 1] = static_cast<StorageIndex>(inner.size());
  }
  set_compressed_columns(lower_, outer, inner);
  ldlt_.analyzePattern(lower_);
  pattern_id_ = A.pattern_id();
}

namespace {

// D^-1/2 of a symmetric positive definite 3x3 block; false when it is not positive definite.
bool inverse_square_root(const Mat3& D, Mat3& W) {
  const Eigen::SelfAdjointEigenSolver<Mat3> eigen(D);
  const Vec3& lambda = eigen.eigenvalues();
  if (!(lambda.minCoeff() > 0.0)) return false;
  const Mat3& Q = eigen.eigenvectors();
  W = Q * lambda.cwiseSqrt().cwiseInverse().asDiagonal() * Q.transpose();
  return true;
}

}  // namespace

bool ScalarCholeskyPreconditioner::compute(const BlockSparseMatrix& A, bool block_scaled,
                                           const std::vector<DiagonalAddition>& additions) {
  if (pattern_id_ != A.pattern_id()) analyze(A);
  const int n = A.num_vertices();
  block_scaled_ = block_scaled;
  valid_ = false;
  if (block_scaled) {
    // W_i = (D_i + additions)^-1/2.
    scale_.resize(n);
    for (int i = 0; i < n; ++i) {
      if (solved_[i]) scale_[i] = Eigen::Map<const Mat3>(A.block_values(A.diagonal(i)));
    }
    for (const DiagonalAddition& add : additions) scale_[add.vertex] += add.block;
    for (int i = 0; i < n; ++i) {
      if (solved_[i] && !inverse_square_root(Mat3(scale_[i]), scale_[i])) return false;
    }
  } else {
    scale_.clear();
  }
  // S_ji (j >= i) = trace(A_ij) / 3, or trace(W_i A_ij W_j) / 3.
  double* values = lower_.valuePtr();
  const int* rows = lower_.innerIndexPtr();
  for (int i = 0; i < n; ++i) {
    for (int k = lower_.outerIndexPtr()[i]; k < lower_.outerIndexPtr()[i + 1]; ++k) {
      if (source_[k] < 0) {
        values[k] = 1.0;
        continue;
      }
      const Eigen::Map<const Mat3> block(A.block_values(source_[k]));
      values[k] = (block_scaled ? (scale_[i] * block * scale_[rows[k]]).trace() : block.trace()) / 3.0;
    }
  }
  for (const Dropped& drop : dropped_) {
    const Eigen::Map<const Vec3> d(A.values().data() + A.diagonal_only_value(drop.block));
    const double s = block_scaled ? (scale_[drop.i] * d.asDiagonal() * scale_[drop.j]).trace()
                                  : d.sum();
    values[drop.diagonal] += std::fabs(s) / 3.0;
  }
  ldlt_.factorize(lower_);
  valid_ = ldlt_.info() == Eigen::Success && ldlt_.vectorD().minCoeff() > 0.0;
  return valid_;
}

// z = W^T P^T L^-T D^-1 L^-1 P W r, with P S P^T = L D L^T (unit lower L from Eigen's
// simplicial LDL^T, its fill-reducing AMD ordering P), one pass over L for the three
// coordinates.
void ScalarCholeskyPreconditioner::apply(const Eigen::VectorXd& r, Eigen::VectorXd& z) const {
  const int n = static_cast<int>(solved_.size());
  const auto& L = ldlt_.matrixL().nestedExpression();
  const Eigen::VectorXd& D = ldlt_.vectorD();
  const auto* perm = ldlt_.permutationP().indices().data();
  work_.resize(n);
  for (int i = 0; i < n; ++i) {
    const Vec3 ri = solved_[i] ? Vec3(r.segment<3>(3 * i)) : Vec3::Zero();
    work_[perm[i]] = block_scaled_ && solved_[i] ? Vec3(scale_[i] * ri) : ri;
  }
  const auto* outer = L.outerIndexPtr();
  const auto* inner = L.innerIndexPtr();
  const double* value = L.valuePtr();
  for (int j = 0; j < n; ++j) {
    const Vec3 yj = work_[j];
    for (auto k = outer[j]; k < outer[j + 1]; ++k) work_[inner[k]] -= value[k] * yj;
  }
  for (int j = 0; j < n; ++j) work_[j] /= D[j];
  for (int j = n - 1; j >= 0; --j) {
    Vec3 yj = work_[j];
    for (auto k = outer[j]; k < outer[j + 1]; ++k) yj -= value[k] * work_[inner[k]];
    work_[j] = yj;
  }
  z.resize(3 * static_cast<Eigen::Index>(n));
  for (int i = 0; i < n; ++i) {
    const Vec3& yi = work_[perm[i]];
    z.segment<3>(3 * i) = !solved_[i] ? Vec3::Zero() : block_scaled_ ? Vec3(scale_[i] * yi) : yi;
  }
}

}  // namespace tissu
