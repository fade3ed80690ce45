// Implicit integrators: backward Euler (the paper's eq. 11), BDF-2 and implicit midpoint,
// all solved in velocity form with Newton's method, the analytic force Jacobian written
// straight into the step's matrix (SystemMatrix), preconditioned conjugate gradients
// (sparse Cholesky or block Jacobi preconditioner, Model::implicit.linear_solver), contact
// with obstacles as velocity constraints inside the solve (ContactSet) or, on request
// (Model::implicit.contact), a barrier potential (BarrierContact, which also holds the
// cloth apart from itself with either model), and a backtracking line search on the
// incremental potential or the residual (Model::implicit.line_search).
// Pinned vertices are constraints removed from the solve. Equations and choices:
// docs/implicit.md.
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
  int newton_iterations = 0;      // Newton iterations (system matrices assembled)
  int linear_solves = 0;          // PCG solves (one per Newton iteration)
  int cg_iterations = 0;          // total over the solves
  int factorizations = 0;         // factorizations of the Cholesky or scalar preconditioner
  bool converged = false;         // final residual <= newton_tolerance * initial residual, or
                                  // the last whole step moved no vertex more than
                                  // newton_motion_tolerance
  double initial_residual = 0.0;  // at the initial guess v = v_n
  double final_residual = 0.0;
  std::vector<double> residuals;     // initial, then after each Newton iteration
  std::vector<double> step_lengths;  // line-search step per iteration
  std::vector<int> cg_per_iteration;  // per solve
  std::vector<double> velocity_changes;  // per iteration, the largest |v change| taken, m/s
  // Per iteration: the longest step the barrier's line search allowed (0.9 of the first
  // touch of an obstacle; 1 where nothing would touch, and without the barrier), the
  // merit's change at the length taken (J for the incremental potential, sqrt(kg) m/s for
  // the residual; 0 where no length decreased it) and, with the barrier only, the vertices
  // within dhat of an obstacle after it.
  std::vector<double> feasible_lengths;
  std::vector<double> merit_changes;
  std::vector<int> barrier_contacts;
  bool cg_failed = false;  // some linear solve missed cg_tolerance (its result was
                           // still used, guarded by the line search)
  bool line_search_failed = false;  // some direction decreased the merit at no length
                                    // tried (it was then taken whole)
  int contacts = 0;                 // vertices in contact at the end of the step
  int barrier_pairs = 0;            // of those, self pairs and mesh feature pairs within
                                    // the barrier's dhat (counted once per pair)
  int stuck_contacts = 0;           // of those, held by friction
  int contact_changes = 0;          // Newton iterations after which the contacts changed
  int unresolved_contacts = 0;      // vertices left inside an obstacle (moved out by the
                                    // step's collision stage)
  // Processor time of the stages, s (std::clock; profiling, not used by the method).
  double seconds_jacobian = 0.0;  // assembly of the system matrix
  double seconds_preconditioner = 0.0;
  double seconds_cg = 0.0;
  double seconds_residual = 0.0;  // force evaluations for residuals and the line search
  double seconds_contact = 0.0;   // contact detection and constraint updates
};

// One step of each method (model.dt from state.t, model.implicit options). Advances
// state.x and state.v, leaves state.t and state.step to the caller (step() advances them).
// Pinned vertices are not touched. Records the statistics in ws (newton_iterations,
// cg_iterations) and returns the full report (valid until the next implicit step on ws).
const ImplicitReport& backward_euler(const Model& model, State& state, Workspace& ws);
const ImplicitReport& bdf2(const Model& model, State& state, Workspace& ws);
const ImplicitReport& implicit_midpoint(const Model& model, State& state, Workspace& ws);

// The report of the last implicit (sub)step taken with ws (through step() or the functions
// above); null before the first.
const ImplicitReport* last_implicit_report(const Workspace& ws);

// Substeps: a step of model.dt is solved as n equal substeps so that no vertex moves more
// than kSubstepMotion of an edge relative to its neighbours in one solve, where one Newton
// iteration is no longer a good linearization (impacts, whipping). The prediction from the
// start velocities: n = ceil(dt r / kSubstepMotion), with r (1/s) the largest of
// |v_a - v_b| / |x_a - x_b| over the edges and, for vertices that may reach an obstacle
// within the step (a moving one placed where it starts and where it ends the step), their
// approach speed over the mean rest edge length; at most kMaxSubsteps.
constexpr double kSubstepMotion = 0.5;
constexpr int kMaxSubsteps = 16;
int implicit_substeps(const Model& model, const State& state);
// The largest change of an edge's vector between positions x0 and x1, over the edge's
// length at x0: how far a vertex moved relative to its neighbours, in edges. A step is
// planned with fewer substeps than implicit_substeps when its last step moved no vertex
// more than kMotionLimit of an edge per substep; if one of its substeps then does, the step
// is taken again with the substeps implicit_substeps asks for.
double relative_motion(const Model& model, const Vec3List& x0, const Vec3List& x1);
constexpr double kMotionLimit = 2.0 * kSubstepMotion;

// The step of model.integrator (BackwardEuler, Bdf2 or ImplicitMidpoint) over model.dt, in
// the substeps planned from the last step's motion (backward Euler, BDF-2) or predicted by
// implicit_substeps (the midpoint rule), never fewer than keep a vertex from passing an
// obstacle within one substep nor than the collision stage's energy rule last needed; a substep whose Newton solve neither
// converged nor reduced its residual a hundredfold (tenfold without an energy gain, in a
// scene nothing drives) has the step taken again in twice as many substeps (up to
// kMaxSubsteps). ws holds the totals over the substeps and attempts, the count planned and
// the count kept.
void integrate_implicit(const Model& model, State& state, Workspace& ws);

// The work moving obstacles did on the cloth over an implicit step of h from `start` (at
// start.t) to `end`, J: each free vertex's contact impulse, what the method's forces do not
// explain, dotted with the velocity of the moving surface nearest it (within an edge).
double moving_obstacles_work(const Model& model, const State& start, const State& end, double h,
                             Workspace& ws);

}  // namespace tissu
