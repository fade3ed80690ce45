#include "physics/linear_solver.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <iterator>

#include "physics/parallel.h"
#include "physics/serial_openmp.h"

namespace tissu {

namespace {

// Sorted, duplicate-free pairs into compressed rows.
void compress(int num_vertices, const std::vector<std::pair<int, int>>& pairs,
              std::vector<int>& row_start, std::vector<int>& col) {
  row_start.assign(num_vertices + 1, 0);
  for (const auto& [i, j] : pairs) row_start[i + 1] += 1;
  for (int i = 0; i < num_vertices; ++i) row_start[i + 1] += row_start[i];
  col.resize(pairs.size());
  for (size_t b = 0; b < pairs.size(); ++b) col[b] = pairs[b].second;
}

void sort_unique(std::vector<std::pair<int, int>>& pairs) {
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
}

int find_in(const std::vector<int>& row_start, const std::vector<int>& col, int i, int j) {
  const auto begin = col.begin() + row_start[i], end = col.begin() + row_start[i + 1];
  const auto it = std::lower_bound(begin, end, j);
  return (it != end && *it == j) ? static_cast<int>(it - col.begin()) : -1;
}

}  // namespace

void BlockSparseMatrix::set_pattern(int num_vertices, std::vector<std::pair<int, int>> full,
                                    std::vector<std::pair<int, int>> diagonal_only) {
  static uint64_t next_pattern_id = 0;
  pattern_id_ = ++next_pattern_id;
  num_vertices_ = num_vertices;
  sort_unique(full);
  sort_unique(diagonal_only);
  // A pair that is also full is stored once, as a full block.
  std::vector<std::pair<int, int>> only;
  only.reserve(diagonal_only.size());
  std::set_difference(diagonal_only.begin(), diagonal_only.end(), full.begin(), full.end(),
                      std::back_inserter(only));
  compress(num_vertices, full, row_start_, col_);
  compress(num_vertices, only, drow_start_, dcol_);
  diag_.assign(num_vertices, -1);
  for (int i = 0; i < num_vertices; ++i) diag_[i] = find(i, i);
  values_.assign(9 * col_.size() + 3 * dcol_.size(), 0.0);
}

int BlockSparseMatrix::find(int i, int j) const { return find_in(row_start_, col_, i, j); }

int BlockSparseMatrix::find_entry(int i, int j, int r, int c) const {
  const int b = find(i, j);
  if (b >= 0) return 9 * b + 3 * c + r;
  if (r != c) return -1;
  const int d = find_in(drow_start_, dcol_, i, j);
  return d >= 0 ? static_cast<int>(9 * col_.size()) + 3 * d + r : -1;
}

void BlockSparseMatrix::set_zero() { std::fill(values_.begin(), values_.end(), 0.0); }

void BlockSparseMatrix::multiply(const Eigen::VectorXd& x, Eigen::VectorXd& y,
                                 int threads) const {
  y.resize(3 * static_cast<Eigen::Index>(num_vertices_));
  parallel_for_ranges(threads, num_vertices_, kRowsPerItem,
                      [&](int first, int end) { multiply_rows(x, y, first, end); });
}

void BlockSparseMatrix::multiply_rows(const Eigen::VectorXd& x, Eigen::VectorXd& y, int first,
                                      int end) const {
  const double* px = x.data();
  const double* full = values_.data();
  const double* diagonal_only = values_.data() + 9 * col_.size();
  for (int i = first; i < end; ++i) {
    double y0 = 0.0, y1 = 0.0, y2 = 0.0;
    for (int b = row_start_[i]; b < row_start_[i + 1]; ++b) {
      const double* a = full + 9 * static_cast<size_t>(b);
      const double* xj = px + 3 * static_cast<size_t>(col_[b]);
      y0 += a[0] * xj[0] + a[3] * xj[1] + a[6] * xj[2];
      y1 += a[1] * xj[0] + a[4] * xj[1] + a[7] * xj[2];
      y2 += a[2] * xj[0] + a[5] * xj[1] + a[8] * xj[2];
    }
    for (int b = drow_start_[i]; b < drow_start_[i + 1]; ++b) {
      const double* d = diagonal_only + 3 * static_cast<size_t>(b);
      const double* xj = px + 3 * static_cast<size_t>(dcol_[b]);
      y0 += d[0] * xj[0];
      y1 += d[1] * xj[1];
      y2 += d[2] * xj[2];
    }
    y[3 * i] = y0;
    y[3 * i + 1] = y1;
    y[3 * i + 2] = y2;
  }
}

Eigen::MatrixXd BlockSparseMatrix::to_dense() const {
  Eigen::MatrixXd dense = Eigen::MatrixXd::Zero(3 * num_vertices_, 3 * num_vertices_);
  for (int i = 0; i < num_vertices_; ++i) {
    for (int b = row_start_[i]; b < row_start_[i + 1]; ++b) {
      dense.block<3, 3>(3 * i, 3 * col_[b]) = Eigen::Map<const Mat3>(block_values(b));
    }
    for (int b = drow_start_[i]; b < drow_start_[i + 1]; ++b) {
      const double* d = values_.data() + 9 * col_.size() + 3 * static_cast<size_t>(b);
      for (int c = 0; c < 3; ++c) dense(3 * i + c, 3 * dcol_[b] + c) = d[c];
    }
  }
  return dense;
}

void set_compressed_columns(Eigen::SparseMatrix<double>& m,
                            const std::vector<Eigen::SparseMatrix<double>::StorageIndex>& outer,
                            const std::vector<Eigen::SparseMatrix<double>::StorageIndex>& inner) {
  const Eigen::Index n = static_cast<Eigen::Index>(outer.size()) - 1;
  m.resize(n, n);
  m.resizeNonZeros(static_cast<Eigen::Index>(inner.size()));
  std::copy(outer.begin(), outer.end(), m.outerIndexPtr());
  std::copy(inner.begin(), inner.end(), m.innerIndexPtr());
  std::fill_n(m.valuePtr(), inner.size(), 1.0);
}

void BlockJacobiPreconditioner::compute(const BlockSparseMatrix& A) {
  const int n = A.num_vertices();
  inverse_.resize(n);
  for (int i = 0; i < n; ++i) {
    const int d = A.diagonal(i);
    if (d < 0) {
      inverse_[i].setZero();
      continue;
    }
    const Mat3 block = Eigen::Map<const Mat3>(A.block_values(d));
    Eigen::LLT<Mat3> llt(block);
    if (llt.info() == Eigen::Success) {
      inverse_[i] = llt.solve(Mat3::Identity());
    } else {
      // Not positive definite (cannot happen for M - h df/dv - h^2 df/dx with the projected
      // stiffness): fall back to the inverse of the absolute diagonal.
      inverse_[i].setZero();
      for (int c = 0; c < 3; ++c) {
        const double a = std::fabs(block(c, c));
        inverse_[i](c, c) = a > 0.0 ? 1.0 / a : 0.0;
      }
    }
  }
}

void BlockJacobiPreconditioner::apply(const Eigen::VectorXd& r, Eigen::VectorXd& z) const {
  z.resize(r.size());
  for (size_t i = 0; i < inverse_.size(); ++i) {
    z.segment<3>(3 * i).noalias() = inverse_[i] * r.segment<3>(3 * i);
  }
}

namespace {

// The fill-reducing ordering, chosen once per pattern: CHOLMOD computes both AMD's and its
// nested dissection's (METIS with a constrained minimum degree) and keeps the one with the
// smaller factor. By default it tries nested dissection only when AMD's is very poor, and
// on cloth it is not: on 50,000 triangles AMD's factor takes 2262 Mflop, nested
// dissection's 1467 (docs/implicit.md). Its cost, paid once, is that of a few
// factorizations' worth of time at most.
void choose_best_of_amd_and_nested_dissection(cholmod_common& common) {
  const auto nested_dissection = common.method[3];  // CHOLMOD's default suite: 3 is NESDIS
  common.nmethods = 2;
  common.method[0] = common.method[1];  // AMD, without a user ordering
  common.method[0].ordering = CHOLMOD_AMD;
  common.method[1] = nested_dissection;
  common.method[1].ordering = CHOLMOD_NESDIS;
}

// CHOLMOD's approximate minimum degree ordering alone.
void amd_only(cholmod_common& common) {
  common.nmethods = 1;
  common.method[0].ordering = CHOLMOD_AMD;
}

}  // namespace

void CholeskyPreconditioner::analyze(const BlockSparseMatrix& A) {
  const int n = A.num_vertices();
  const Eigen::Index dofs = 3 * static_cast<Eigen::Index>(n);
  // Column c of the lower triangle is row c of the upper one (A is symmetric): for each
  // coordinate row R, the full-block entries A(R, C) with C >= R.
  std::vector<std::pair<Eigen::Index, int64_t>> entries;  // (C, value index) of one row
  using StorageIndex = Eigen::SparseMatrix<double>::StorageIndex;
  std::vector<StorageIndex> outer(dofs + 1, 0);  // compressed columns of lower_
  std::vector<StorageIndex> inner;
  source_.clear();
  dropped_.clear();
  solved_.assign(dofs, 0);
  diagonal_block_.assign(9 * static_cast<size_t>(n), -1);
  for (int i = 0; i < n; ++i) {
    for (int a = 0; a < 3; ++a) {
      const Eigen::Index R = 3 * i + a;
      entries.clear();
      if (A.diagonal(i) >= 0) {
        solved_[R] = 1;
        for (int b = A.row_begin(i); b < A.row_end(i); ++b) {
          const int j = A.block_column(b);
          for (int c = 0; c < 3; ++c) {
            const Eigen::Index C = 3 * static_cast<Eigen::Index>(j) + c;
            // Column-major 3x3 block: entry (a, c) at 3 c + a.
            if (C >= R) entries.emplace_back(C, 9 * static_cast<int64_t>(b) + 3 * c + a);
          }
        }
        // The extra pairs of row i (columns beyond it), from extra_values_.
        auto e = std::lower_bound(extra_pairs_.begin(), extra_pairs_.end(), std::make_pair(i, 0));
        for (; e != extra_pairs_.end() && e->first == i; ++e) {
          const int64_t k = 9 * (e - extra_pairs_.begin());
          for (int c = 0; c < 3; ++c) {
            entries.emplace_back(3 * static_cast<Eigen::Index>(e->second) + c, -2 - (k + 3 * c + a));
          }
        }
        std::sort(entries.begin(), entries.end());
      } else {
        entries.emplace_back(R, -1);
      }
      for (const auto& [C, index] : entries) {
        if (C / 3 == i && index >= 0) {
          diagonal_block_[9 * static_cast<size_t>(i) + 3 * a + C % 3] =
              static_cast<int64_t>(source_.size());
        }
        if (C == R) {
          // Diagonal-only blocks of this row are dropped; their magnitudes go here.
          for (int d = A.diagonal_only_begin(i); d < A.diagonal_only_end(i); ++d) {
            if (A.diagonal_only_column(d) == i) continue;
            dropped_.emplace_back(static_cast<int64_t>(source_.size()),
                                  static_cast<int64_t>(A.diagonal_only_value(d)) + a);
          }
        }
        inner.push_back(static_cast<StorageIndex>(C));
        source_.push_back(index);
      }
      outer[R + 1] = static_cast<StorageIndex>(inner.size());
    }
  }
  // The compressed columns as built (each sorted by row, so value k of lower_ is
  // source_[k]), then the ordering and symbolic analysis once.
  set_compressed_columns(lower_, outer, inner);
  if (extra_pairs_.empty()) {
    choose_best_of_amd_and_nested_dissection(llt_.cholmod());
  } else {
    amd_only(llt_.cholmod());  // analysed again as the extra pairs change: the cheap ordering
  }
  llt_.cholmod().print = 0;  // silent: a factor short of positive definite is reported
                             // by compute() and handled by the caller
  llt_.analyzePattern(lower_);
  pattern_id_ = A.pattern_id();
  analyses_ += 1;
}

bool CholeskyPreconditioner::gather_off_pattern(const std::vector<OffPatternBlock>& blocks) {
  extra_values_.assign(9 * extra_pairs_.size(), 0.0);
  for (const OffPatternBlock& b : blocks) {
    const auto e = std::lower_bound(extra_pairs_.begin(), extra_pairs_.end(),
                                    std::make_pair(b.row, b.column));
    if (e == extra_pairs_.end() || *e != std::make_pair(b.row, b.column)) return false;
    double* target = extra_values_.data() + 9 * (e - extra_pairs_.begin());
    for (int k = 0; k < 9; ++k) target[k] += b.block.data()[k];
  }
  return true;
}

bool CholeskyPreconditioner::compute(const BlockSparseMatrix& A,
                                     const std::vector<DiagonalAddition>& additions,
                                     const std::vector<OffPatternBlock>* off_pattern,
                                     double diagonal_shift) {
  static const std::vector<OffPatternBlock> kNone;
  const std::vector<OffPatternBlock>& blocks = off_pattern ? *off_pattern : kNone;
  if (!gather_off_pattern(blocks)) {
    // New pairs: the next analysis takes them with the old ones, unless the old ones
    // outnumber them twice over (then only the pairs in use now).
    std::vector<std::pair<int, int>> wanted;
    for (const OffPatternBlock& b : blocks) wanted.emplace_back(b.row, b.column);
    sort_unique(wanted);
    if (extra_pairs_.size() <= 2 * wanted.size()) {
      wanted.insert(wanted.end(), extra_pairs_.begin(), extra_pairs_.end());
      sort_unique(wanted);
    }
    extra_pairs_.swap(wanted);
    pattern_id_ = 0;
    gather_off_pattern(blocks);
  }
  if (pattern_id_ != A.pattern_id()) analyze(A);
  double* values = lower_.valuePtr();
  const std::vector<double>& a = A.values();
  for (size_t k = 0; k < source_.size(); ++k) {
    const int64_t from = source_[k];
    values[k] = from >= 0 ? a[from] : (from == -1 ? 1.0 : extra_values_[-2 - from]);
  }
  for (const auto& [diagonal, index] : dropped_) values[diagonal] += std::fabs(a[index]);
  for (const DiagonalAddition& add : additions) {
    for (int c = 0; c < 3; ++c) {
      for (int r = c; r < 3; ++r) {
        const int64_t k = diagonal_block_[9 * static_cast<size_t>(add.vertex) + 3 * c + r];
        if (k >= 0) values[k] += add.block(r, c);
      }
    }
  }
  if (diagonal_shift > 0.0) {
    // Along each vertex's stiff directions only: its diagonal block D gains
    // diagonal_shift (D - lambda_min(D) I), which leaves the directions where its mass
    // alone holds it as they are.
    for (size_t i = 0; 9 * i < diagonal_block_.size(); ++i) {
      const int64_t* k = &diagonal_block_[9 * i];  // entry (r, c) at 3 c + r, r >= c
      if (k[0] < 0) continue;
      Mat3 D;
      for (int c = 0; c < 3; ++c) {
        for (int r = c; r < 3; ++r) D(r, c) = D(c, r) = values[k[3 * c + r]];
      }
      Eigen::SelfAdjointEigenSolver<Mat3> eigen;
      eigen.computeDirect(D, Eigen::EigenvaluesOnly);
      const Mat3 shift = diagonal_shift * (D - eigen.eigenvalues()(0) * Mat3::Identity());
      for (int c = 0; c < 3; ++c) {
        for (int r = c; r < 3; ++r) values[k[3 * c + r]] += shift(r, c);
      }
    }
  }
  {
    // CHOLMOD's regions open four threads, fixed when Debian built it: on two cores they
    // cost 1.6 times the processor time of one thread and take cores from the
    // simulation's own threads.
    const SerialOpenMpScope on_this_thread;
    llt_.factorize(lower_);
  }
  valid_ = llt_.info() == Eigen::Success;
  return valid_;
}

void CholeskyPreconditioner::apply(const Eigen::VectorXd& r, Eigen::VectorXd& z) const {
  z = llt_.solve(r);
  for (Eigen::Index k = 0; k < z.size(); ++k) {
    if (!solved_[k]) z[k] = 0.0;
  }
}

void OffPatternBlocks::add(int i, int j, const Mat3& block) {
  if (i < j) {
    blocks_.push_back({i, j, block});
  } else {
    blocks_.push_back({j, i, block.transpose()});
  }
}

void OffPatternBlocks::add_product(const Eigen::VectorXd& x, Eigen::VectorXd& y) const {
  for (const OffPatternBlock& b : blocks_) {
    y.segment<3>(3 * b.row) += b.block * x.segment<3>(3 * b.column);
    y.segment<3>(3 * b.column) += b.block.transpose() * x.segment<3>(3 * b.row);
  }
}

// Hestenes-Stiefel conjugate gradients with a left preconditioner (Saad, "Iterative
// Methods for Sparse Linear Systems", 2nd ed., Algorithm 9.1); with a filter, every
// vector it builds is kept in the filter's range.
CgResult solve_pcg(const BlockSparseMatrix& A, const Preconditioner& P, const Eigen::VectorXd& b,
                   double tolerance, int max_iterations, Eigen::VectorXd& x, CgWorkspace& work,
                   const Eigen::VectorXd* weights, const SolveFilter* filter,
                   const MatrixAddition* addition) {
  CgResult result;
  auto product = [&](const Eigen::VectorXd& y, Eigen::VectorXd& Ay) {
    A.multiply(y, Ay, work.threads);
    if (addition) addition->add_product(y, Ay);
  };
  auto norm = [weights](const Eigen::VectorXd& y) {
    return weights ? std::sqrt(y.cwiseAbs2().dot(*weights)) : y.norm();
  };
  auto keep = [filter](Eigen::VectorXd& y) {
    if (filter) filter->apply(y);
  };
  Eigen::VectorXd& r = work.r;
  Eigen::VectorXd& z = work.z;
  Eigen::VectorXd& p = work.p;
  Eigen::VectorXd& Ap = work.Ap;
  r = b;
  keep(r);
  const double b_norm = norm(r);
  if (x.size() != b.size()) x.setZero(b.size());
  keep(x);
  if (b_norm == 0.0) {
    x.setZero();
    result.converged = true;
    return result;
  }
  product(x, Ap);
  r = b - Ap;
  keep(r);
  double r_norm = norm(r);
  const double target = tolerance * b_norm;
  if (r_norm <= target) {
    result.relative_residual = r_norm / b_norm;
    result.converged = true;
    return result;
  }
  P.apply(r, z);
  keep(z);
  p = z;
  double rz = r.dot(z);
  // Rounding can make CG diverge on an ill-conditioned system (its residual then grows far
  // beyond |b|, and p^T A p reaches zero): an iterate worse than the start is never
  // returned, the best one is.
  Eigen::VectorXd& best_x = work.best_x;
  const double start_norm = r_norm;
  double best_norm = r_norm;
  bool best_kept = false;  // best_x holds the iterate whose residual is best_norm
  while (result.iterations < max_iterations) {
    product(p, Ap);
    keep(Ap);
    const double pAp = p.dot(Ap);
    if (!(pAp > 0.0)) {
      result.breakdown = true;
      break;
    }
    const double alpha = rz / pAp;
    x.noalias() += alpha * p;
    r.noalias() -= alpha * Ap;
    result.iterations += 1;
    r_norm = norm(r);
    if (r_norm <= target) {
      result.converged = true;
      break;
    }
    if (r_norm < best_norm) {
      best_norm = r_norm;
      best_kept = false;
    } else if (!best_kept) {
      best_x = x - alpha * p;  // the iterate before this one, the best so far
      best_kept = true;
    }
    P.apply(r, z);
    keep(z);
    const double rz_next = r.dot(z);
    p = z + (rz_next / rz) * p;
    rz = rz_next;
  }
  if (!result.converged && r_norm > start_norm && best_kept) {
    x = best_x;
    keep(x);
    r_norm = best_norm;
  }
  result.relative_residual = r_norm / b_norm;
  return result;
}

}  // namespace tissu
