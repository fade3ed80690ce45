#include "physics/implicit.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <ctime>
#include <utility>

#include "physics/block_triplets.h"
#include "physics/force_plan.h"
#include "physics/forces.h"
#include "physics/linear_solver.h"
#include "physics/step_scratch.h"

namespace tissu {

// Scratch memory and caches of the implicit integrators, kept in StepScratch::implicit so
// that steps after the first allocate nothing: the Jacobian triplets (their capacity), the
// block pattern of the system matrix and, for every triplet, the slot of the matrix value
// it adds to.
struct ImplicitSolver {
  BlockTriplets dfdx, dfdv;
  // Per triplet: its (row, column) key when the slot was found, and the slot
  // (index into A.values(), or one of the negative codes below).
  std::vector<uint64_t> key_x, key_v;
  std::vector<int> slot_x, slot_v;
  std::vector<uint8_t> pattern_pinned;  // the pin flags the pattern was built for
  bool has_pattern = false;

  BlockSparseMatrix A;  // M - beta df/dv - beta^2 df/dx over the free vertices
  BlockJacobiPreconditioner block_jacobi;
  CholeskyPreconditioner cholesky;

  CgWorkspace cg;
  Eigen::VectorXd rhs, dv, shift;
  Eigen::VectorXd weights;     // (3V) 1/m per free coordinate, 0 for pinned ones, 1/kg

  Vec3List x_base, v_base;       // (V) the step equation's affine part, m and m/s
  Vec3List v, x;                 // (V) current Newton iterate and its positions
  Vec3List v_try, x_try, f_try;  // (V) line-search trial
  Vec3List f_lin;                // (V) forces at the first linearization point, N
  Vec3List x_saved, v_saved;     // (V) x_n, v_n (become State::previous after the step)

  ImplicitReport report;
};

namespace {

// Stage times are processor time (std::clock), which other processes do not inflate.
double processor_seconds_since(std::clock_t t0) {
  return static_cast<double>(std::clock() - t0) / CLOCKS_PER_SEC;
}

constexpr int kPinned = -1;   // the triplet touches a pinned vertex: not in the solve
constexpr int kMissing = -2;  // its block is not in the pattern
// Cholesky preconditioner: a factorization costs about as much as 30 CG iterations (5000
// triangles). A fresh factor needs 2-10 iterations, one kept from earlier steps 5-20 while
// the cloth moves gently, thousands once it folds or hits an obstacle. PCG with a kept
// factor gives up after this many and refactors.
constexpr int kStaleFactorCgIterations = 20;
constexpr int kMaxHalvings = 12;              // line search: smallest step 2^-12
constexpr double kSufficientDecrease = 1e-4;  // Armijo constant on |g|

inline uint64_t key_of(const Eigen::Triplet<double>& t) {
  return (static_cast<uint64_t>(static_cast<uint32_t>(t.row())) << 32) |
         static_cast<uint32_t>(t.col());
}

// The step equation g(v) = M (v - v_base) - beta f(x_base + beta v, v, t_force) = 0.
struct StepEquation {
  double beta = 0.0;     // s
  double t_force = 0.0;  // s
  // The unknown's change over the step is about warm_scale (v_n - v_{n-1}): 1 when the
  // unknown is v_{n+1}, 1/2 when it is the midpoint velocity.
  double warm_scale = 1.0;
};

// The state's history holds the step before this one (same step size).
bool has_history(const Model& model, const State& state) {
  const size_t n = static_cast<size_t>(model.num_vertices());
  return state.previous.step + 1 == state.step && state.previous.dt == model.dt &&
         state.previous.x.size() == n && state.previous.v.size() == n;
}

// Positions of the iterate v: x_base + beta v for free vertices, x_n for pinned ones.
void positions(const Model& model, const ImplicitSolver& s, const StepEquation& eq,
               const Vec3List& x_n, const Vec3List& v, Vec3List& x) {
  x.resize(v.size());
  for (int i = 0; i < model.num_vertices(); ++i) {
    x[i] = model.pinned[i] ? x_n[i] : Vec3(s.x_base[i] + eq.beta * v[i]);
  }
}

// |g(v)|_{M^-1} over the free vertices given the forces f at (x(v), v).
double residual_norm(const Model& model, const ImplicitSolver& s, const StepEquation& eq,
                     const Vec3List& v, const Vec3List& f) {
  double sum = 0.0;
  for (int i = 0; i < model.num_vertices(); ++i) {
    if (model.pinned[i]) continue;
    const Vec3 g = model.mass[i] * (v[i] - s.v_base[i]) - eq.beta * f[i];
    sum += model.mass[i] > 0.0 ? g.squaredNorm() / model.mass[i] : g.squaredNorm();
  }
  return std::sqrt(sum);
}

// Block pattern of the free-vertex system: every (row, column) vertex pair the Jacobian
// triplets touch, plus the diagonal (mass) blocks. Pairs whose triplets are all diagonal
// entries (the bending Jacobian's second-ring pairs) get diagonal-only blocks.
void build_pattern(const Model& model, ImplicitSolver& s) {
  const int n = model.num_vertices();
  std::vector<std::pair<int, int>> full, diagonal_only;
  full.reserve(s.dfdx.entries.size() / 9 + n);
  for (int i = 0; i < n; ++i) {
    if (!model.pinned[i]) full.emplace_back(i, i);
  }
  for (const BlockTriplets* triplets : {&s.dfdx, &s.dfdv}) {
    std::pair<int, int> last_full(-1, -1), last_diagonal(-1, -1);
    for (const Eigen::Triplet<double>& t : triplets->entries) {
      const std::pair<int, int> b(t.row() / 3, t.col() / 3);
      const bool off_diagonal = t.row() % 3 != t.col() % 3;
      std::pair<int, int>& last = off_diagonal ? last_full : last_diagonal;
      if (b == last) continue;  // consecutive entries of one 3x3 block
      last = b;
      if (model.pinned[b.first] || model.pinned[b.second]) continue;
      (off_diagonal ? full : diagonal_only).push_back(b);
    }
  }
  s.A.set_pattern(n, std::move(full), std::move(diagonal_only));
  s.pattern_pinned = model.pinned;
  s.has_pattern = true;
  s.key_x.clear();
  s.key_v.clear();
  s.slot_x.clear();
  s.slot_v.clear();
}

// Slot in A.values() of one triplet; kPinned if it touches a pinned vertex, kMissing if its
// block is not in the pattern.
int find_slot(const Model& model, const BlockSparseMatrix& A, const Eigen::Triplet<double>& t) {
  const int i = t.row() / 3, j = t.col() / 3;
  if (model.pinned[i] || model.pinned[j]) return kPinned;
  const int slot = A.find_entry(i, j, t.row() % 3, t.col() % 3);
  return slot >= 0 ? slot : kMissing;
}

// Adds scale * triplets into A, reusing the cached slots (checked against the triplet
// keys, since terms such as the wind skip degenerate triangles and change the triplet
// sequence). Returns false if a block is missing from the pattern (the caller rebuilds it).
bool scatter(const Model& model, const BlockTriplets& triplets, std::vector<uint64_t>& keys,
             std::vector<int>& slots, double scale, BlockSparseMatrix& A) {
  const size_t count = triplets.entries.size();
  if (keys.size() != count) {
    keys.resize(count, ~uint64_t{0});
    slots.resize(count, kMissing);
  }
  double* values = A.values().data();
  for (size_t k = 0; k < count; ++k) {
    const Eigen::Triplet<double>& t = triplets.entries[k];
    const uint64_t key = key_of(t);
    if (keys[k] != key) {
      keys[k] = key;
      slots[k] = find_slot(model, A, t);
    }
    const int slot = slots[k];
    if (slot == kPinned) continue;
    if (slot == kMissing) {
      keys[k] = ~uint64_t{0};
      return false;
    }
    values[slot] += scale * t.value();
  }
  return true;
}

// Fills A = M - beta df/dv - beta^2 df/dx from the Jacobian triplets (free vertices only).
void assemble(const Model& model, ImplicitSolver& s, double beta) {
  if (!s.has_pattern || s.pattern_pinned != model.pinned ||
      s.A.num_vertices() != model.num_vertices()) {
    build_pattern(model, s);
  }
  for (int attempt = 0; attempt < 2; ++attempt) {
    s.A.set_zero();
    for (int i = 0; i < model.num_vertices(); ++i) {
      if (model.pinned[i]) continue;
      double* d = s.A.block_values(s.A.diagonal(i));
      d[0] += model.mass[i];
      d[4] += model.mass[i];
      d[8] += model.mass[i];
    }
    if (scatter(model, s.dfdx, s.key_x, s.slot_x, -beta * beta, s.A) &&
        scatter(model, s.dfdv, s.key_v, s.slot_v, -beta, s.A)) {
      return;
    }
    // A block outside the pattern: rebuild the pattern from the current triplets, retry.
    build_pattern(model, s);
  }
}

// rhs += scale df/dx y over the free rows and columns (after assemble(), which validated
// the slots of the df/dx triplets).
void add_dfdx_product(const ImplicitSolver& s, double scale, const Eigen::VectorXd& y,
                      Eigen::VectorXd& rhs) {
  for (size_t k = 0; k < s.dfdx.entries.size(); ++k) {
    if (s.slot_x[k] == kPinned) continue;
    const Eigen::Triplet<double>& t = s.dfdx.entries[k];
    rhs[t.row()] += scale * t.value() * y[t.col()];
  }
}

// Solves s.A s.dv = s.rhs by PCG from the s.dv given. With linear_solver cholesky, the
// factor of an earlier matrix is tried first: when it has not converged within
// kStaleFactorCgIterations, the current matrix is factorized and PCG goes on from there.
// Block Jacobi on request, or when a factorization fails (A not positive definite).
CgResult linear_solve(const ImplicitOptions& opt, ImplicitSolver& s, int max_cg,
                      ImplicitReport& report) {
  auto pcg = [&](const Preconditioner& p, int max_iterations) {
    const std::clock_t t0 = std::clock();
    const CgResult r =
        solve_pcg(s.A, p, s.rhs, opt.cg_tolerance, max_iterations, s.dv, s.cg, &s.weights);
    report.seconds_cg += processor_seconds_since(t0);
    return r;
  };
  CgResult stale;
  if (opt.linear_solver == LinearSolver::Cholesky) {
    if (s.cholesky.valid() && s.cholesky.pattern_id() == s.A.pattern_id()) {
      stale = pcg(s.cholesky, kStaleFactorCgIterations);
      if (stale.converged) return stale;
    }
    std::clock_t t0 = std::clock();
    const bool factorized = s.cholesky.compute(s.A);
    report.seconds_preconditioner += processor_seconds_since(t0);
    if (factorized) {
      report.factorizations += 1;
      CgResult r = pcg(s.cholesky, max_cg);
      r.iterations += stale.iterations;
      return r;
    }
  }
  std::clock_t t0 = std::clock();
  s.block_jacobi.compute(s.A);
  report.seconds_preconditioner += processor_seconds_since(t0);
  CgResult r = pcg(s.block_jacobi, max_cg);
  r.iterations += stale.iterations;
  return r;
}

// Newton's method on g(v) = 0, starting from v = v_n (already in s.v). The first iteration
// linearizes the forces at the start of the step (x_n, v_n), as Baraff & Witkin 1998 do;
// later ones at the current iterate (x_base + beta v, v). Each direction solves
//   (M - beta df/dv - beta^2 df/dx) dv = M (v_base - v) + beta f_lin
//                                        + beta df/dx (x(v) - x_lin)
// (the last term is zero after the first iteration, where the right-hand side is -g(v))
// by PCG (linear_solve), and a backtracking line search on |g|_{M^-1} accepts the step.
void newton_solve(const Model& model, const State& state, Workspace& ws, ImplicitSolver& s,
                  const StepEquation& eq) {
  const int n = model.num_vertices();
  StepScratch& scratch = scratch_of(ws);
  ForcePlan& plan = scratch.forces;
  Vec3List& f = scratch.f;
  const ImplicitOptions& opt = model.implicit;
  const int threads = force_threads(ws.threads, model);
  ImplicitReport& report = s.report;
  {
    // Reset, keeping the vectors' capacity.
    ImplicitReport fresh;
    std::swap(fresh.residuals, report.residuals);
    std::swap(fresh.step_lengths, report.step_lengths);
    std::swap(fresh.cg_per_iteration, report.cg_per_iteration);
    fresh.residuals.clear();
    fresh.step_lengths.clear();
    fresh.cg_per_iteration.clear();
    report = std::move(fresh);
  }

  // Residual at the initial guess.
  std::clock_t t0 = std::clock();
  positions(model, s, eq, state.x, s.v, s.x);
  compute_forces(model, s.x, s.v, eq.t_force, f, plan, threads);
  double r = residual_norm(model, s, eq, s.v, f);
  report.seconds_residual += processor_seconds_since(t0);
  const double r0 = r;
  report.initial_residual = r0;
  report.residuals.push_back(r);
  const double target = opt.newton_tolerance * r0;
  report.converged = (r <= target);

  // CG measures residuals in the same M^-1 norm as Newton; pinned entries weigh nothing.
  int free_dofs = 0;
  s.weights.resize(3 * n);
  for (int i = 0; i < n; ++i) {
    free_dofs += model.pinned[i] ? 0 : 3;
    const double w = model.pinned[i] ? 0.0 : (model.mass[i] > 0.0 ? 1.0 / model.mass[i] : 1.0);
    s.weights.segment<3>(3 * i).setConstant(w);
  }
  const int max_cg = std::max(50, free_dofs);

  for (int k = 0; k < opt.max_newton_iterations && !report.converged && free_dofs > 0; ++k) {
    // Linearization point and forces there.
    t0 = std::clock();
    const Vec3List* x_lin = &s.x;
    const Vec3List* f_lin = &f;
    if (k == 0) {
      x_lin = &state.x;
      compute_forces(model, state.x, s.v, eq.t_force, s.f_lin, plan, threads);
      f_lin = &s.f_lin;
    }
    s.dfdx.clear();
    s.dfdv.clear();
    compute_force_jacobian(model, *x_lin, s.v, eq.t_force, /*project_psd=*/true, s.dfdx, s.dfdv);

    // Right-hand side M (v_base - v) + beta f_lin (+ beta df/dx (x - x_lin)), free rows.
    s.rhs.setZero(3 * n);
    for (int i = 0; i < n; ++i) {
      if (model.pinned[i]) continue;
      s.rhs.segment<3>(3 * i) = model.mass[i] * (s.v_base[i] - s.v[i]) + eq.beta * (*f_lin)[i];
    }
    assemble(model, s, eq.beta);
    if (k == 0) {
      s.shift.setZero(3 * n);
      for (int i = 0; i < n; ++i) {
        if (!model.pinned[i]) s.shift.segment<3>(3 * i) = s.x[i] - state.x[i];
      }
      add_dfdx_product(s, eq.beta, s.shift, s.rhs);
    }
    report.seconds_jacobian += processor_seconds_since(t0);

    // Linear solve by PCG (Cholesky or block-Jacobi preconditioner). The first iteration
    // starts from the previous step's velocity change (consecutive steps change velocities
    // alike), later ones from 0.
    s.dv.setZero(3 * n);
    if (k == 0 && has_history(model, state)) {
      for (int i = 0; i < n; ++i) {
        if (model.pinned[i]) continue;
        s.dv.segment<3>(3 * i) = eq.warm_scale * (state.v[i] - state.previous.v[i]);
      }
    }
    const CgResult cg = linear_solve(opt, s, max_cg, report);
    report.newton_iterations += 1;
    report.cg_iterations += cg.iterations;
    report.cg_per_iteration.push_back(cg.iterations);
    if (!cg.converged) report.cg_failed = true;

    // Backtracking line search on |g|: accept the first step length with sufficient
    // decrease; otherwise the best decrease found; otherwise no step.
    t0 = std::clock();
    double alpha = 1.0, best_alpha = 0.0, best_r = r, accepted = 0.0;
    for (int trial = 0; trial <= kMaxHalvings; ++trial, alpha *= 0.5) {
      s.v_try = s.v;
      for (int i = 0; i < n; ++i) {
        if (!model.pinned[i]) s.v_try[i] += alpha * s.dv.segment<3>(3 * i);
      }
      positions(model, s, eq, state.x, s.v_try, s.x_try);
      compute_forces(model, s.x_try, s.v_try, eq.t_force, s.f_try, plan, threads);
      const double r_try = residual_norm(model, s, eq, s.v_try, s.f_try);
      if (r_try <= (1.0 - kSufficientDecrease * alpha) * r) {
        accepted = alpha;
        r = r_try;
        break;
      }
      if (r_try < best_r) {
        best_r = r_try;
        best_alpha = alpha;
      }
    }
    if (accepted == 0.0 && best_alpha > 0.0) {
      accepted = best_alpha;
      for (int i = 0; i < n; ++i) {
        s.v_try[i] = s.v[i];
        if (!model.pinned[i]) s.v_try[i] += best_alpha * s.dv.segment<3>(3 * i);
      }
      positions(model, s, eq, state.x, s.v_try, s.x_try);
      compute_forces(model, s.x_try, s.v_try, eq.t_force, s.f_try, plan, threads);
      r = residual_norm(model, s, eq, s.v_try, s.f_try);
    }
    report.seconds_residual += processor_seconds_since(t0);
    report.step_lengths.push_back(accepted);
    report.residuals.push_back(r);
    if (accepted == 0.0) {
      // The direction does not reduce the residual: keep the current iterate. After the
      // first iteration (linearized at the start of the step) Newton continues from the
      // current iterate; after a later one it stops.
      if (k == 0) continue;
      break;
    }
    std::swap(s.v, s.v_try);
    std::swap(s.x, s.x_try);
    std::swap(f, s.f_try);
    report.converged = (r <= target);
  }
  report.final_residual = r;
  ws.newton_iterations = report.newton_iterations;
  ws.cg_iterations = report.cg_iterations;
}

ImplicitSolver& solver_of(Workspace& ws) {
  StepScratch& scratch = scratch_of(ws);
  if (!scratch.implicit) scratch.implicit = std::make_shared<ImplicitSolver>();
  return *scratch.implicit;
}

// Saves x_n, v_n before the step; afterwards they become State::previous.
void begin_step(const Model& model, const State& state, Workspace& ws, ImplicitSolver& s) {
  const size_t n = static_cast<size_t>(model.num_vertices());
  scratch_of(ws).f.resize(n);
  s.f_lin.resize(n);
  s.f_try.resize(n);
  s.x_saved = state.x;
  s.v_saved = state.v;
}

void end_step(const Model& model, State& state, ImplicitSolver& s) {
  std::swap(state.previous.x, s.x_saved);
  std::swap(state.previous.v, s.v_saved);
  state.previous.step = state.step;
  state.previous.dt = model.dt;
}

// Backward Euler in velocity form: x_base = x_n, v_base = v_n, beta = h.
void backward_euler_stage(const Model& model, State& state, Workspace& ws, ImplicitSolver& s) {
  const double h = model.dt;
  s.x_base = state.x;
  s.v_base = state.v;
  s.v = state.v;
  newton_solve(model, state, ws, s, StepEquation{h, state.t + h});
  for (int i = 0; i < model.num_vertices(); ++i) {
    if (model.pinned[i]) continue;
    state.v[i] = s.v[i];
    state.x[i] = s.x[i];
  }
}

}  // namespace

// Eq. 11 of the paper, v_{n+1} = v_n + h M^-1 f(x_{n+1}, v_{n+1}), x_{n+1} = x_n + h v_{n+1}.
const ImplicitReport& backward_euler(const Model& model, State& state, Workspace& ws) {
  ImplicitSolver& s = solver_of(ws);
  begin_step(model, state, ws, s);
  backward_euler_stage(model, state, ws, s);
  end_step(model, state, s);
  return s.report;
}

// BDF-2: x_{n+1} = 4/3 x_n - 1/3 x_{n-1} + 2/3 h v_{n+1},
//        v_{n+1} = 4/3 v_n - 1/3 v_{n-1} + 2/3 h M^-1 f(x_{n+1}, v_{n+1}).
// Started (and restarted whenever the previous state is not the one of the step before,
// with the same h and model) by one backward Euler step.
const ImplicitReport& bdf2(const Model& model, State& state, Workspace& ws) {
  ImplicitSolver& s = solver_of(ws);
  const int n = model.num_vertices();
  const StepHistory& previous = state.previous;
  const bool history = has_history(model, state);
  begin_step(model, state, ws, s);
  if (!history) {
    backward_euler_stage(model, state, ws, s);
  } else {
    const double h = model.dt;
    s.x_base.resize(n);
    s.v_base.resize(n);
    for (int i = 0; i < n; ++i) {
      s.x_base[i] = (4.0 / 3.0) * state.x[i] - (1.0 / 3.0) * previous.x[i];
      s.v_base[i] = (4.0 / 3.0) * state.v[i] - (1.0 / 3.0) * previous.v[i];
    }
    s.v = state.v;
    newton_solve(model, state, ws, s, StepEquation{2.0 * h / 3.0, state.t + h});
    for (int i = 0; i < n; ++i) {
      if (model.pinned[i]) continue;
      state.v[i] = s.v[i];
      state.x[i] = s.x[i];
    }
  }
  end_step(model, state, s);
  return s.report;
}

// Implicit midpoint: v_{n+1} = v_n + h M^-1 f((x_n + x_{n+1})/2, (v_n + v_{n+1})/2),
// x_{n+1} = x_n + h (v_n + v_{n+1})/2. With the midpoint velocity w = (v_n + v_{n+1})/2
// this is a backward Euler step of h/2 for w: M (w - v_n) = h/2 f(x_n + h/2 w, w).
const ImplicitReport& implicit_midpoint(const Model& model, State& state, Workspace& ws) {
  ImplicitSolver& s = solver_of(ws);
  begin_step(model, state, ws, s);
  const double h = model.dt;
  s.x_base = state.x;
  s.v_base = state.v;
  s.v = state.v;
  newton_solve(model, state, ws, s, StepEquation{0.5 * h, state.t + 0.5 * h, 0.5});
  for (int i = 0; i < model.num_vertices(); ++i) {
    if (model.pinned[i]) continue;
    state.x[i] += h * s.v[i];
    state.v[i] = 2.0 * s.v[i] - state.v[i];
  }
  end_step(model, state, s);
  return s.report;
}

const ImplicitReport* last_implicit_report(const Workspace& ws) {
  return ws.scratch && ws.scratch->implicit ? &ws.scratch->implicit->report : nullptr;
}

void integrate_implicit(const Model& model, State& state, Workspace& ws) {
  switch (model.integrator) {
    case Integrator::Bdf2:
      bdf2(model, state, ws);
      break;
    case Integrator::ImplicitMidpoint:
      implicit_midpoint(model, state, ws);
      break;
    default:
      backward_euler(model, state, ws);
      break;
  }
}

}  // namespace tissu
