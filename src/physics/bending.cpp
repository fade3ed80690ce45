// Bending energy, forces and Jacobian; see bending.h and docs/bending.md.
#include "physics/bending.h"

#include <Eigen/Dense>
#include <algorithm>
#include <utility>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/error.h"
#include "physics/bending_simd.h"

namespace tissu {

namespace {

// Q = sum_T A_T (D11 w_uu w_uu^T + D22 w_vv w_vv^T + 4 D66 w_uv w_uv^T), row by row
// straight from the stencils. Each entry sums its terms in stencil order, as a triplet
// list would (so Q has the same bits), without the list: 40 triplets of 16 bytes per
// triangle were 640 MB at a million triangles, and most of the set-up's time.
Eigen::SparseMatrix<double, Eigen::RowMajor> assemble_stiffness(const BendingModel& model, int V) {
  const std::vector<BendingStencil>& stencils = model.stencils;
  const double c_uu = model.bending_weft, c_vv = model.bending_warp, c_uv = 4.0 * model.twist;
  auto term = [&](const BendingStencil& st, int a, int b) {
    return st.area * (c_uu * st.w_uu[a] * st.w_uu[b] + c_vv * st.w_vv[a] * st.w_vv[b] +
                      c_uv * st.w_uv[a] * st.w_uv[b]);
  };
  // The (stencil, slot) pairs of each vertex, in stencil order.
  std::vector<int> first(static_cast<size_t>(V) + 1, 0);
  for (const BendingStencil& st : stencils) {
    for (int v : st.vertex) ++first[v + 1];
  }
  for (int v = 0; v < V; ++v) first[v + 1] += first[v];
  std::vector<std::pair<int, int>> slots(static_cast<size_t>(first[V]));
  std::vector<int> fill(first.begin(), first.end() - 1);
  for (int s = 0; s < static_cast<int>(stencils.size()); ++s) {
    const std::vector<int>& vertex = stencils[s].vertex;
    for (int a = 0; a < static_cast<int>(vertex.size()); ++a) slots[fill[vertex[a]]++] = {s, a};
  }

  std::vector<int> outer(static_cast<size_t>(V) + 1, 0), inner;
  std::vector<double> values;
  std::vector<int> entry_of(static_cast<size_t>(V), -1);  // column -> entry in `row`
  std::vector<std::pair<int, double>> row;
  for (int r = 0; r < V; ++r) {
    row.clear();
    for (int k = first[r]; k < first[r + 1]; ++k) {
      const BendingStencil& st = stencils[slots[k].first];
      const int a = slots[k].second;
      for (int b = 0; b < static_cast<int>(st.vertex.size()); ++b) {
        const int c = st.vertex[b];
        if (entry_of[c] < 0) {
          entry_of[c] = static_cast<int>(row.size());
          row.emplace_back(c, term(st, a, b));
        } else {
          row[entry_of[c]].second += term(st, a, b);
        }
      }
    }
    std::sort(row.begin(), row.end());
    for (const auto& [c, value] : row) {
      inner.push_back(c);
      values.push_back(value);
      entry_of[c] = -1;
    }
    outer[r + 1] = static_cast<int>(inner.size());
  }
  return Eigen::Map<const Eigen::SparseMatrix<double, Eigen::RowMajor>>(
      V, V, static_cast<Eigen::Index>(values.size()), outer.data(), inner.data(), values.data());
}

}  // namespace

BendingModel build_bending(const TriList& triangles, const Vec2List& rest_uv, double bending_weft,
                           double bending_warp, const std::vector<uint8_t>& pinned) {
  if (!(bending_weft >= 0.0)) {
    throw InputError("bending: weft flexural rigidity must be >= 0 N*m, got " +
                     std::to_string(bending_weft));
  }
  BendingModel model;
  model.bending_weft = bending_weft;
  model.bending_warp = bending_warp < 0.0 ? bending_weft : bending_warp;
  model.twist = 0.25 * (model.bending_weft + model.bending_warp);
  model.num_vertices = static_cast<int>(rest_uv.size());
  const int V = model.num_vertices;
  // The stencils and their diagnostics (bending_stencil.h).
  static_cast<BendingStencils&>(model) = build_bending_stencils(triangles, rest_uv, pinned);

  model.stiffness = assemble_stiffness(model, V);
  return model;
}

namespace {

using RowMatrixX3 = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
static_assert(sizeof(Vec3) == 3 * sizeof(double), "Vec3List must be contiguous doubles");

void check_size(const BendingModel& model, size_t n, const char* what) {
  if (static_cast<int>(n) != model.num_vertices) {
    throw std::invalid_argument(std::string("bending: ") + what + " has " + std::to_string(n) +
                                " vertices, model has " + std::to_string(model.num_vertices));
  }
}

// Positions relative to their mean. Q annihilates translations, so Q X = Q (X - mean); the
// subtraction keeps round-off proportional to the sheet's size, not to its distance from
// the origin.
RowMatrixX3 centered(const Vec3List& x) {
  const Eigen::Map<const RowMatrixX3> X(x[0].data(), static_cast<Eigen::Index>(x.size()), 3);
  return X.rowwise() - bending_origin(x).transpose();
}

}  // namespace

Vec3 bending_origin(const Vec3List& x) {
  if (x.empty()) return Vec3::Zero();
  const Eigen::Map<const RowMatrixX3> X(x[0].data(), static_cast<Eigen::Index>(x.size()), 3);
  return X.colwise().mean().transpose();
}

double bending_energy(const BendingModel& model, const Vec3List& x) {
  check_size(model, x.size(), "x");
  if (model.num_vertices == 0) return 0.0;
  const RowMatrixX3 X = centered(x);
  const RowMatrixX3 QX = model.stiffness * X;
  return 0.5 * X.cwiseProduct(QX).sum();
}

void center_positions(const Vec3List& x, const Vec3& origin, CenteredPositions& xc) {
  center_positions_simd(x, origin, xc);
}

void center_positions(const BendingModel& model, const Vec3List& x, CenteredPositions& xc) {
  check_size(model, x.size(), "x");
  center_positions(x, bending_origin(x), xc);
}

void add_bending_forces(const BendingModel& model, const CenteredPositions& xc, int first,
                        int end, VertexForces out) {
  add_bending_forces_simd(model, xc, first, end, out);
}

void add_bending_forces(const BendingModel& model, const Vec3List& x, const Vec3& origin,
                        int first, int end, VertexForces out) {
  check_size(model, x.size(), "x");
  CenteredPositions xc;
  center_positions(x, origin, xc);
  add_bending_forces(model, xc, first, end, out);
}

void add_bending_forces_scalar(const BendingModel& model, const Vec3List& x,
                               const Vec3& origin, int first, int end, VertexForces out) {
  const auto& Q = model.stiffness;
  const int* starts = Q.outerIndexPtr();
  const int* columns = Q.innerIndexPtr();
  const double* values = Q.valuePtr();
  for (int i = first; i < end; ++i) {
    Vec3 qx = Vec3::Zero();
    for (int k = starts[i]; k < starts[i + 1]; ++k) qx += values[k] * (x[columns[k]] - origin);
    out[i] -= qx;
  }
}

void add_bending_jacobian(const BendingModel& model, JacobianSink& sink) {
  if (sink.cx == 0.0) return;
  const auto& Q = model.stiffness;
  for (int i = 0; i < Q.outerSize(); ++i) {
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(Q, i); it; ++it) {
      sink.add_identity(i, static_cast<int>(it.col()), -sink.cx * it.value());
    }
  }
}

}  // namespace tissu
