// Implicit integrators: backward Euler (the paper's eq. 11), BDF-2 and implicit midpoint,
// all solved in velocity form with Newton's method, the analytic force Jacobian
// (compute_force_jacobian), preconditioned conjugate gradients (sparse Cholesky or block
// Jacobi preconditioner, Model::implicit.linear_solver) and a
// backtracking line search on the nonlinear residual. Pinned vertices are constraints
// removed from the solve. Equations and choices: docs/implicit.md.
//
// Each method solves, for the unknown velocity v (one 3-vector per free vertex),
//   g(v) = M (v - v_base) - beta f(x_base + beta v, v, t_f) = 0             (kg m/s)
//   backward Euler:   x_base = x_n, v_base = v_n, beta = h, t_f = t_n + h;
//                     x_{n+1} = x_n + h v, v_{n+1} = v.
//   BDF-2:            x_base = 4/3 x_n - 1/3 x_{n-1}, v_base = 4/3 v_n - 1/3 v_{n-1},
//                     beta = 2/3 h, t_f = t_n + h; x_{n+1} = x_base + beta v, v_{n+1} = v
//                     (the first step, and any step without the previous state, is a
//                     backward Euler step).
//   implicit midpoint: x_base = x_n, v_base = v_n, beta = h/2, t_f = t_n + h/2, v the
//                     midpoint velocity; v_{n+1} = 2 v - v_n, x_{n+1} = x_n + h v.
#pragma once

#include <vector>

#include "physics/model.h"
#include "physics/workspace.h"

namespace tissu {

// What the Newton solve of one step did. Residuals are |g|_{M^-1} = sqrt(sum |g_i|^2 / m_i)
// over the free vertices (sqrt(kg) m/s: the velocity error in the kinetic-energy norm).
struct ImplicitReport {
  int newton_iterations = 0;      // linear solves performed
  int cg_iterations = 0;          // total over the Newton iterations
  int factorizations = 0;         // Cholesky factorizations (linear_solver cholesky)
  bool converged = false;         // final residual <= newton_tolerance * initial residual
  double initial_residual = 0.0;  // at the initial guess v = v_n
  double final_residual = 0.0;
  std::vector<double> residuals;     // initial, then after each Newton iteration
  std::vector<double> step_lengths;  // line-search step per iteration (0 = step rejected)
  std::vector<int> cg_per_iteration;
  bool cg_failed = false;  // some linear solve missed cg_tolerance (its result was
                           // still used, guarded by the line search)
  // Processor time of the stages, s (std::clock; profiling, not used by the method).
  double seconds_jacobian = 0.0;  // compute_force_jacobian + assembly of the system matrix
  double seconds_preconditioner = 0.0;
  double seconds_cg = 0.0;
  double seconds_residual = 0.0;  // force evaluations for residuals and the line search
};

// One step of each method (model.dt, model.implicit options). Advances state.x and
// state.v, leaves state.t and state.step to the caller (step() advances them). Pinned
// vertices are not touched. Records the statistics in ws (newton_iterations,
// cg_iterations) and returns the full report (valid until the next implicit step on ws).
const ImplicitReport& backward_euler(const Model& model, State& state, Workspace& ws);
const ImplicitReport& bdf2(const Model& model, State& state, Workspace& ws);
const ImplicitReport& implicit_midpoint(const Model& model, State& state, Workspace& ws);

// The report of the last implicit step taken with ws (through step() or the functions
// above); null before the first.
const ImplicitReport* last_implicit_report(const Workspace& ws);

// The step of model.integrator (BackwardEuler, Bdf2 or ImplicitMidpoint).
void integrate_implicit(const Model& model, State& state, Workspace& ws);

}  // namespace tissu
