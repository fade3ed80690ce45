#include "physics/implicit.h"

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/Sparse>

#include "physics/block_triplets.h"
#include "physics/forces.h"

namespace tissu {

namespace {

using SparseMatrix = Eigen::SparseMatrix<double>;

Eigen::Map<const Eigen::VectorXd> flat(const Vec3List& list) {
  return {list.empty() ? nullptr : list[0].data(), static_cast<Eigen::Index>(3 * list.size())};
}

}  // namespace

// Baraff & Witkin 1998, one Newton iteration of backward Euler in velocity form:
//   (M - h df/dv - h^2 df/dx) dv = h (f0 + h df/dx v0),  v1 = v0 + dv,  x1 = x0 + h v1.
// The stress term of df/dx is projected to keep the system positive definite.
void integrate_implicit(const Model& model, State& state, Workspace& ws) {
  const double h = model.dt;
  const int n = model.num_vertices();
  compute_forces(model, state.x, state.v, state.t, ws.f);

  BlockTriplets dfdx, dfdv;
  compute_force_jacobian(model, state.x, state.v, state.t, /*project_psd=*/true, dfdx, dfdv);
  SparseMatrix Kx(3 * n, 3 * n), Kv(3 * n, 3 * n);
  Kx.setFromTriplets(dfdx.entries.begin(), dfdx.entries.end());
  Kv.setFromTriplets(dfdv.entries.begin(), dfdv.entries.end());

  const Eigen::VectorXd v0 = flat(state.v);
  Eigen::VectorXd rhs = h * (flat(ws.f) + h * (Kx * v0));
  SparseMatrix A = -h * Kv - (h * h) * Kx;
  Eigen::VectorXd mass(3 * n);
  for (int i = 0; i < n; ++i) mass.segment<3>(3 * i).setConstant(model.mass[i]);
  A += SparseMatrix(mass.asDiagonal());

  // Pinned vertices: dv = 0, their rows and columns become identity.
  for (int k = 0; k < A.outerSize(); ++k) {
    for (SparseMatrix::InnerIterator it(A, k); it; ++it) {
      const bool pinned_row = model.pinned[it.row() / 3], pinned_col = model.pinned[it.col() / 3];
      if (pinned_row || pinned_col) it.valueRef() = (it.row() == it.col()) ? 1.0 : 0.0;
    }
  }
  for (int i = 0; i < n; ++i) {
    if (model.pinned[i]) rhs.segment<3>(3 * i).setZero();
  }

  Eigen::ConjugateGradient<SparseMatrix, Eigen::Lower | Eigen::Upper> cg;
  cg.setTolerance(1e-8);
  cg.compute(A);
  const Eigen::VectorXd dv = cg.solve(rhs);
  ws.newton_iterations = 1;
  ws.cg_iterations = static_cast<int>(cg.iterations());

  for (int i = 0; i < n; ++i) {
    if (model.pinned[i]) continue;
    state.v[i] += dv.segment<3>(3 * i);
    state.x[i] += h * state.v[i];
  }
}

}  // namespace tissu
