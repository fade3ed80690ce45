#include "physics/system_matrix.h"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <utility>

#include "physics/air_damping.h"
#include "physics/bending.h"
#include "physics/block_triplets.h"
#include "physics/membrane.h"
#include "physics/parallel.h"
#include "physics/wind.h"

namespace tissu {

// Keeps each triangle's nine blocks, weighted as SlotSink weighs them, at 81 t of `out`
// (pinned corners' blocks too: the sum over each block's sources skips them).
class TriangleBlockSink : public JacobianSink {
 public:
  TriangleBlockSink(double beta, double* out) : JacobianSink(-beta * beta, -beta), out_(out) {}

  void add_triangle(int t, const Tri&, const Mat3* blocks) override {
    double* target = out_ + 81 * static_cast<size_t>(t);
    for (int k = 0; k < 9; ++k) std::copy_n(blocks[k].data(), 9, target + 9 * k);
  }
  void add(int, int, const Mat3&) override {
    throw std::logic_error("triangle block sink: a term that is not per triangle");
  }

 private:
  double* out_;
};

// Adds weighted Jacobian blocks into a value array of the matrix's pattern, scaled by -1
// (A = M - beta df/dv - beta^2 df/dx: the sink's weights are -beta^2 and -beta with the
// sign folded in by the caller). Blocks of pinned vertices are skipped.
class SlotSink : public JacobianSink {
 public:
  SlotSink(const SystemMatrix& system, const Model& model, double beta, double* values)
      : JacobianSink(-beta * beta, -beta), system_(system), model_(model), values_(values) {}

  void add_triangle(int t, const Tri&, const Mat3* blocks) override {
    const int* slots = system_.triangle_slots_.data() + 9 * static_cast<size_t>(t);
    for (int k = 0; k < 9; ++k) {
      if (slots[k] < 0) continue;
      double* target = values_ + 9 * static_cast<size_t>(slots[k]);
      const double* source = blocks[k].data();
      for (int e = 0; e < 9; ++e) target[e] += source[e];
    }
  }

  void add(int i, int j, const Mat3& block) override {
    if (model_.pinned[i] || model_.pinned[j]) return;
    const int b = system_.A_.find(i, j);
    if (b < 0) {
      throw std::logic_error("system matrix: no block for vertices " + std::to_string(i) +
                             ", " + std::to_string(j));
    }
    double* target = values_ + 9 * static_cast<size_t>(b);
    for (int e = 0; e < 9; ++e) target[e] += block.data()[e];
  }

  void add_identity(int i, int j, double s) override {
    if (model_.pinned[i] || model_.pinned[j]) return;
    for (int c = 0; c < 3; ++c) {
      const int entry = system_.A_.find_entry(i, j, c, c);
      if (entry < 0) {
        throw std::logic_error("system matrix: no entry for vertices " + std::to_string(i) +
                               ", " + std::to_string(j));
      }
      values_[entry] += s;
    }
  }

 private:
  const SystemMatrix& system_;
  const Model& model_;
  double* values_;
};

void SystemMatrix::plan(const Model& model) {
  const bool bending = model.bending != nullptr;
  if (planned_mesh_ == model.mesh_id && planned_pins_ == model.pinned &&
      planned_bending_ == bending) {
    return;
  }
  const int n = model.num_vertices();
  std::vector<std::pair<int, int>> full, diagonal_only;
  full.reserve(9 * model.triangles.size() + n);
  for (int i = 0; i < n; ++i) {
    if (!model.pinned[i]) full.emplace_back(i, i);
  }
  for (const Tri& tri : model.triangles) {
    for (int a = 0; a < 3; ++a) {
      for (int b = 0; b < 3; ++b) {
        if (!model.pinned[tri[a]] && !model.pinned[tri[b]]) full.emplace_back(tri[a], tri[b]);
      }
    }
  }
  if (bending) {
    BlockTriplets pairs;
    TripletSink collect(1.0, 0.0, pairs);
    add_bending_jacobian(*model.bending, collect);
    for (size_t k = 0; k < pairs.entries.size(); k += 9) {
      const int i = pairs.entries[k].row() / 3, j = pairs.entries[k].col() / 3;
      if (!model.pinned[i] && !model.pinned[j]) diagonal_only.emplace_back(i, j);
    }
  }
  A_.set_pattern(n, std::move(full), std::move(diagonal_only));

  triangle_slots_.assign(9 * model.triangles.size(), -1);
  for (size_t t = 0; t < model.triangles.size(); ++t) {
    const Tri& tri = model.triangles[t];
    for (int a = 0; a < 3; ++a) {
      for (int b = 0; b < 3; ++b) {
        if (model.pinned[tri[a]] || model.pinned[tri[b]]) continue;
        triangle_slots_[9 * t + 3 * a + b] = A_.find(tri[a], tri[b]);
      }
    }
  }
  // Each block's sources in triangle order: a counting sort of the slots, stable in t.
  slot_sources_start_.assign(A_.num_blocks() + 1, 0);
  for (int slot : triangle_slots_) {
    if (slot >= 0) slot_sources_start_[slot + 1] += 1;
  }
  for (int b = 0; b < A_.num_blocks(); ++b) slot_sources_start_[b + 1] += slot_sources_start_[b];
  slot_sources_.resize(slot_sources_start_.back());
  std::vector<int> filled(slot_sources_start_.begin(), slot_sources_start_.end() - 1);
  for (size_t k = 0; k < triangle_slots_.size(); ++k) {
    const int slot = triangle_slots_[k];
    if (slot >= 0) slot_sources_[filled[slot]++] = 9 * static_cast<int64_t>(k);
  }
  constant_beta_ = -1.0;
  planned_mesh_ = model.mesh_id;
  planned_pins_ = model.pinned;
  planned_bending_ = bending;
}

void SystemMatrix::add_constant_terms(const Model& model, double beta,
                                      std::vector<double>& values) const {
  for (int i = 0; i < model.num_vertices(); ++i) {
    if (model.pinned[i]) continue;
    double* d = values.data() + 9 * static_cast<size_t>(A_.diagonal(i));
    d[0] += model.mass[i];
    d[4] += model.mass[i];
    d[8] += model.mass[i];
  }
  SlotSink sink(*this, model, beta, values.data());
  if (model.bending) add_bending_jacobian(*model.bending, sink);
  if (model.air_damping) add_air_damping_jacobian(model, *model.air_damping, sink);
}

void SystemMatrix::assemble(const Model& model, const Vec3List& x, const Vec3List& v, double t,
                            double beta, bool project_psd, int threads) {
  plan(model);
  if (constant_beta_ != beta) {
    constant_values_.assign(A_.values().size(), 0.0);
    add_constant_terms(model, beta, constant_values_);
    constant_beta_ = beta;
  }
  std::vector<double>& values = A_.values();
  std::copy(constant_values_.begin(), constant_values_.end(), values.begin());
  SlotSink sink(*this, model, beta, values.data());
  const int triangles = model.num_triangles();
  if (threads > 1) {
    add_membrane_blocks(model, x, v, beta, project_psd, threads);
  } else {
    add_membrane_jacobian(model, x, &v, project_psd, 0, triangles, sink);
  }
  if (model.wind) {
    add_wind_jacobian(model, *model.wind, x, v, t, /*position_part=*/!project_psd, 0, triangles,
                      sink);
  }
}

void SystemMatrix::add_membrane_blocks(const Model& model, const Vec3List& x,
                                      const Vec3List& v, double beta, bool project_psd,
                                      int threads) {
  constexpr int kTrianglesPerItem = 256, kRowsPerItem = 256;
  if (beta == 0.0) return;  // the membrane adds nothing (add_membrane_jacobian's weights)
  const int triangles = model.num_triangles();
  triangle_blocks_.resize(81 * static_cast<size_t>(triangles));
  TriangleBlockSink blocks(beta, triangle_blocks_.data());
  parallel_for_ranges(threads, triangles, kTrianglesPerItem, [&](int first, int end) {
    add_membrane_jacobian(model, x, &v, project_psd, first, end, blocks);
  });
  // Each block of A adds its sources in triangle order, as SlotSink would one triangle
  // after the other.
  double* values = A_.values().data();
  parallel_for_ranges(threads, model.num_vertices(), kRowsPerItem, [&](int first, int end) {
    for (int b = A_.row_begin(first); b < A_.row_end(end - 1); ++b) {
      double* target = values + 9 * static_cast<size_t>(b);
      for (int s = slot_sources_start_[b]; s < slot_sources_start_[b + 1]; ++s) {
        const double* source = triangle_blocks_.data() + slot_sources_[s];
        for (int e = 0; e < 9; ++e) target[e] += source[e];
      }
    }
  });
}

void SystemMatrix::add_diagonal(int i, const Mat3& block) {
  double* target = A_.block_values(A_.diagonal(i));
  for (int e = 0; e < 9; ++e) target[e] += block.data()[e];
}

void SystemMatrix::add_block(int i, int j, const Mat3& block) {
  if (!add_block_if_held(i, j, block)) {
    throw std::logic_error("system matrix: no block for vertices " + std::to_string(i) + ", " +
                           std::to_string(j));
  }
}

bool SystemMatrix::add_block_if_held(int i, int j, const Mat3& block) {
  const int b = i == j ? A_.diagonal(i) : A_.find(i, j);
  if (b < 0) return false;
  double* target = A_.block_values(b);
  for (int e = 0; e < 9; ++e) target[e] += block.data()[e];
  return true;
}

}  // namespace tissu
