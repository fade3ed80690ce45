#include "physics/implicit.h"

#include <algorithm>
#include <cmath>
#include <ctime>
#include <utility>

#include "physics/barrier_contact.h"
#include "physics/bending.h"
#include "physics/cloth_contact.h"
#include "physics/contact.h"
#include "physics/diagnostics.h"
#include "physics/force_plan.h"
#include "physics/forces.h"
#include "physics/linear_solver.h"
#include "physics/membrane.h"
#include "physics/scalar_preconditioner.h"
#include "physics/step_scratch.h"
#include "physics/system_matrix.h"
#include "physics/wind.h"

namespace tissu {

// Scratch memory and caches of the implicit integrators, kept in StepScratch::implicit so
// that steps after the first allocate nothing.
struct ImplicitSolver {
  SystemMatrix system;  // A = M - beta df/dv - beta^2 df/dx
  BlockJacobiPreconditioner block_jacobi;
  CholeskyPreconditioner cholesky;
  ScalarCholeskyPreconditioner scalar;
  bool refactor = false;  // the kept factor has become slow: factorize at the next solve
  // (V) the directions each vertex's contacts constrained when the kept factor was made.
  std::vector<ConstrainedDirections> factored_directions;
  CgWorkspace cg;
  Eigen::VectorXd rhs;       // (3V) the Newton right-hand side, kg*m/s
  Eigen::VectorXd dv;        // (3V) Newton direction, m/s
  Eigen::VectorXd reaction;  // (3V) A dv - rhs: the constraint impulses, kg*m/s
  Eigen::VectorXd weights;   // (3V) 1/m per free coordinate, 0 for pinned ones, 1/kg

  Vec3List x_base, v_base;   // (V) the step equation's affine part, m and m/s
  Vec3List x_end_base;       // (V) end-of-step positions at v = 0, m
  Vec3List v, x, f;          // (V) Newton iterate, its force point and forces there
  Vec3List v_try, x_try, f_try, x_end;  // (V) line-search trial; end positions
  Vec3List f_conservative, f_probe;     // (V) potential-merit helpers, N
  Vec3List f_lin;                       // (V) forces at the first linearization point, N
  Eigen::VectorXd shift, shift_product;  // (3V) x(v) - x_n and A times it
  std::vector<double> triangle_energy;  // (T) membrane energies at the iterate, J
  Vec3List x_saved, v_saved;  // (V) x_n, v_n (become State::previous after the step)
  Vec3List x_substep, v_substep;  // (V) start of the substep being judged, m and m/s
  Vec3List work_x, work_v, work_f;  // (V) a midpoint step's supplied work: m, m/s, N

  ContactSet contacts;
  BarrierContact barrier;              // the barrier model's contacts (model.implicit.contact)
  std::vector<PlacedObstacle> placed;  // constrained obstacles at the end of the step
  std::vector<DiagonalAddition> additions;  // constraint stiffness of the factor
  std::vector<double> release;         // (V) pull that releases a contact, kg*m/s
  // (V) velocity changes given to the step as impulses M kick (empty: none), m/s.
  Vec3List kicks;
  // Substeps the collision stage's energy rule needed in the last step (0: none), and the
  // deepest halving it took in the step under way.
  int stage_substeps = 0;
  int stage_depth = 0;
  // How far the last step moved a vertex relative to its neighbours, summed over its
  // substeps, in edges (relative_motion); negative before the first step. Its substeps, and
  // whether it had to be taken again in more than it was planned with.
  double step_motion = -1.0;
  int step_substeps = 0;
  bool step_retaken = false;

  ImplicitReport report;
};

namespace {

// What a step taken again starts from: the constraints' contacts with their memories, and
// the barrier's landings of the step before.
struct ContactMemory {
  ContactSet contacts;
  std::vector<LandingImpulse> landings;
};

ContactMemory contact_memory(const ImplicitSolver& s) {
  return {s.contacts, s.barrier.landings()};
}

void restore(ImplicitSolver& s, const ContactMemory& memory) {
  s.contacts = memory.contacts;
  s.barrier.restore_landings(memory.landings);
}

// Stage times are processor time (std::clock), which other processes do not inflate.
double processor_seconds_since(std::clock_t t0) {
  return static_cast<double>(std::clock() - t0) / CLOCKS_PER_SEC;
}

// Cholesky preconditioner: a factorization costs about as much as 10-20 PCG iterations
// (3000-5000 triangles). A fresh factor needs 1-3 iterations, one kept from earlier steps
// 5-15 while the cloth moves gently, hundreds once it folds or hits an obstacle. PCG with
// a kept factor gives up after kStaleFactorCgIterations and refactors; a kept factor that
// needed more than kRefactorAfter is replaced at the next solve. A kept factor is not
// tried once a contact was added, released or switched between stick and slide since it
// was made: it stiffens the directions the contacts constrained then, and with even one
// or two vertices changed 44-76% of its tries failed (docs/implicit.md).
constexpr int kStaleFactorCgIterations = 20;
constexpr int kRefactorAfter = 10;
constexpr int kMaxHalvings = 12;              // line search: smallest step 2^-12
constexpr double kSufficientDecrease = 1e-4;  // Armijo constant
// Newton iterations beyond max_newton_iterations while the line search shortens the step
// or the contacts change: a step does not end on a fraction of a Newton direction or on
// contacts its last solve did not see, unless this runs out.
constexpr int kExtraNewtonIterations = 8;
// After sticking contacts switch to sliding, Newton may stop only after
// kIterationsAfterSwitch more iterations (sooner if it converges on the new modes), and
// kExtraNewtonIterations beyond while contacts change; never past kSwitchedNewtonFactor
// times its usual limit. Each switch frees the next row of a sheet pushed over a floor, so
// that cap also bounds the rows one step frees.
constexpr int kIterationsAfterSwitch = 2;
constexpr int kSwitchedNewtonFactor = 4;
// End positions deeper than this inside the contact distance count as penetrating, m.
constexpr double kPenetrationTolerance = 1e-9;

// The step equation g(v) = M (v - v_base) - beta f(x_base + beta v, v, t_force) = 0, whose
// solution puts the vertices at x_end_base + beta_end v at the end of the step.
struct StepEquation {
  double h = 0.0;         // step size, s
  double t = 0.0;         // time at the start of the step, s
  double beta = 0.0;      // s
  double t_force = 0.0;   // s
  double beta_end = 0.0;  // s
  double t_end = 0.0;     // s
  // The unknown's change over the step is about warm_scale (v_n - v_{n-1}): 1 when the
  // unknown is v_{n+1}, 1/2 when it is the midpoint velocity.
  double warm_scale = 1.0;
};

// Wind or an obstacle moving within [t0, t1] can put energy into the cloth.
bool supplies_energy(const Model& model, double t0, double t1) {
  return model.wind || has_moving_obstacle(model, t0, t1);
}

// The mass of the vertices that are not pinned, kg.
double free_mass(const Model& model) {
  double mass = 0.0;
  for (int i = 0; i < model.num_vertices(); ++i) mass += model.pinned[i] ? 0.0 : model.mass[i];
  return mass;
}

// The weight of the vertices that are not pinned, N.
double free_weight(const Model& model) {
  return model.gravity ? free_mass(model) * model.gravity->norm() : 0.0;
}

// The state's history holds the step before the one of size h starting at t.
bool has_history(const Model& model, const State& state, double h, double t) {
  const size_t n = static_cast<size_t>(model.num_vertices());
  return state.previous.dt == h && std::fabs(state.previous.t + h - t) <= 1e-9 * h &&
         state.previous.x.size() == n && state.previous.v.size() == n;
}

// Positions x_base + beta v for free vertices, x_n for pinned ones.
void positions(const Model& model, const Vec3List& base, double beta, const Vec3List& x_n,
               const Vec3List& v, Vec3List& x) {
  x.resize(v.size());
  for (int i = 0; i < model.num_vertices(); ++i) {
    x[i] = model.pinned[i] ? x_n[i] : Vec3(base[i] + beta * v[i]);
  }
}

// rhs = M (v_base - v) + beta f (= -g(v)) plus the friction impulses, free rows only.
void step_rhs(const Model& model, const ImplicitSolver& s, const StepEquation& eq,
              const Vec3List& v, const Vec3List& f, Eigen::VectorXd& rhs) {
  rhs.setZero(3 * model.num_vertices());
  for (int i = 0; i < model.num_vertices(); ++i) {
    if (model.pinned[i]) continue;
    rhs.segment<3>(3 * i) = model.mass[i] * (s.v_base[i] - v[i]) + eq.beta * f[i];
  }
  s.contacts.add_friction(v, rhs);
  s.barrier.add_impulses(v, rhs);
}

// The first Newton iteration of a step is linearized at the start of the step, x_n (Baraff
// & Witkin 1998): its right-hand side is M (v_base - v) + beta f(x_n, v) + beta df/dx s
// with s = x(v) - x_n, plus the friction impulses. beta df/dx s comes from the assembled
// matrix A = M - beta df/dv - beta^2 df/dx as (M s - beta df/dv s - A s) / beta, with
// df/dv s = f(x_n, v + s) - f(x_n, v) exactly (the forces are linear in v at fixed x).
void first_rhs(const Model& model, const State& state, ImplicitSolver& s, const StepEquation& eq,
               ForcePlan& plan, int threads) {
  const int n = model.num_vertices();
  compute_forces(model, state.x, s.v, eq.t_force, s.f_lin, plan, threads);
  step_rhs(model, s, eq, s.v, s.f_lin, s.rhs);
  s.shift.setZero(3 * n);
  s.v_try = s.v;
  for (int i = 0; i < n; ++i) {
    if (model.pinned[i]) continue;
    const Vec3 shift = s.x_base[i] + eq.beta * s.v[i] - state.x[i];
    s.shift.segment<3>(3 * i) = shift;
    s.v_try[i] += shift;
  }
  compute_forces(model, state.x, s.v_try, eq.t_force, s.f_probe, plan, threads);
  s.system.matrix().multiply(s.shift, s.shift_product, threads);
  for (int i = 0; i < n; ++i) {
    if (model.pinned[i]) continue;
    const Vec3 damping = s.f_probe[i] - s.f_lin[i];  // df/dv s
    s.rhs.segment<3>(3 * i) += (model.mass[i] * Vec3(s.shift.segment<3>(3 * i)) -
                                eq.beta * damping - Vec3(s.shift_product.segment<3>(3 * i))) /
                               eq.beta;
  }
}

// |S (g(v) - F)|_{M^-1}: the step equation's residual in the directions the contacts leave
// free, with the friction impulses F (sqrt(kg) m/s).
double residual_norm(const Model& model, ImplicitSolver& s, const StepEquation& eq,
                     const Vec3List& v, const Vec3List& f) {
  step_rhs(model, s, eq, v, f, s.reaction);
  s.contacts.filter(s.reaction);
  return std::sqrt(s.reaction.cwiseAbs2().dot(s.weights));
}

// A contact pulling with more than this fraction of its vertex's weight impulse is
// released (a weaker pull is kept, so that contacts balanced at J_n = 0 do not flip
// between released and caught from one step to the next).
constexpr double kReleasePull = 0.01;

// The pull that releases each vertex's contact, kg*m/s (per vertex).
const std::vector<double>& release_impulses(const Model& model, const StepEquation& eq,
                                            ImplicitSolver& s) {
  const double g = model.gravity ? model.gravity->norm() : 0.0;
  s.release.resize(model.num_vertices());
  for (int i = 0; i < model.num_vertices(); ++i) {
    s.release[i] = kReleasePull * model.mass[i] * g * eq.beta;
  }
  return s.release;
}

class ContactFilter : public SolveFilter {
 public:
  explicit ContactFilter(const ContactSet& contacts) : contacts_(contacts) {}
  void apply(Eigen::VectorXd& y) const override { contacts_.filter(y); }

 private:
  const ContactSet& contacts_;
};

// The factor of the Cholesky preconditioner stiffens every constrained direction to
// kConstraintStiffness times its vertex's diagonal entries, so that it approximates the
// inverse of the filtered system (an exact factor of the unconstrained matrix would need
// about one more PCG iteration per constrained direction).
constexpr double kConstraintStiffness = 1e4;

void constraint_stiffness(const ContactSet& contacts, const BlockSparseMatrix& A,
                          std::vector<DiagonalAddition>& additions) {
  additions.clear();
  for (const VertexContact& c : contacts.contacts()) {
    const double* d = A.block_values(A.diagonal(c.vertex));
    const double k = kConstraintStiffness * (d[0] + d[4] + d[8]) / 3.0;
    const Mat3 block = c.mode == ContactMode::Stick ? Mat3(k * Mat3::Identity())
                                                    : Mat3(k * c.normal * c.normal.transpose());
    additions.push_back({c.vertex, block});
  }
}

// Whether the contacts constrain the directions they did when the kept factor was made.
bool same_constrained_directions(const ImplicitSolver& s) {
  for (size_t i = 0; i < s.factored_directions.size(); ++i) {
    if (s.factored_directions[i] != s.contacts.constrained_at(static_cast<int>(i))) {
      return false;
    }
  }
  return true;
}

// Solves S A S dv = S rhs by PCG from the dv given. With linear_solver cholesky, the
// factor of an earlier matrix is tried first: when it has not converged within
// kStaleFactorCgIterations, the current matrix is factorized and PCG goes on from there.
// The scalar factors, cheap to make, are made anew for every solve. Block Jacobi on
// request, or when a factorization fails (A not positive definite).
CgResult linear_solve(const ImplicitOptions& opt, ImplicitSolver& s, int max_cg,
                      ImplicitReport& report) {
  const BlockSparseMatrix& A = s.system.matrix();
  const ContactFilter filter(s.contacts);
  const SolveFilter* constraints = s.contacts.empty() ? nullptr : &filter;
  auto pcg = [&](const Preconditioner& p, int max_iterations) {
    const std::clock_t t0 = std::clock();
    const CgResult r = solve_pcg(A, p, s.rhs, opt.cg_tolerance, max_iterations, s.dv, s.cg,
                                 &s.weights, constraints, s.barrier.coupling());
    report.seconds_cg += processor_seconds_since(t0);
    return r;
  };
  // Factorizes A, with the constrained directions' stiffness added, by compute(); counts
  // and times it. False when the factor is not positive definite.
  auto factorize = [&](auto compute) {
    const std::clock_t t0 = std::clock();
    constraint_stiffness(s.contacts, A, s.additions);
    const bool factorized = compute();
    s.factored_directions.resize(s.v.size());
    for (size_t i = 0; i < s.v.size(); ++i) {
      s.factored_directions[i] = s.contacts.constrained_at(static_cast<int>(i));
    }
    report.seconds_preconditioner += processor_seconds_since(t0);
    if (factorized) report.factorizations += 1;
    return factorized;
  };
  CgResult stale;
  if (opt.linear_solver == LinearSolver::ScalarCholesky ||
      opt.linear_solver == LinearSolver::ScaledScalarCholesky) {
    const bool scaled = opt.linear_solver == LinearSolver::ScaledScalarCholesky;
    if (factorize([&] { return s.scalar.compute(A, scaled, s.additions); })) {
      return pcg(s.scalar, max_cg);
    }
  }
  if (opt.linear_solver == LinearSolver::Cholesky) {
    // Layers held by the barrier stiffen by orders of magnitude from one iteration to the
    // next: a kept factor does not carry over, a fresh one (with the blocks between the
    // layers) converges in one or two iterations.
    const OffPatternBlocks* coupling = s.barrier.coupling();
    if (s.cholesky.valid() && s.cholesky.pattern_id() == A.pattern_id() && !s.refactor &&
        !coupling && same_constrained_directions(s)) {
      stale = pcg(s.cholesky, kStaleFactorCgIterations);
      if (stale.converged) {
        s.refactor = stale.iterations > kRefactorAfter;
        return stale;
      }
    }
    s.refactor = false;
    // Barrier stiffnesses many orders of magnitude beyond the masses (a pair nearly
    // touching) can leave the factor short of positive definite by rounding alone: a
    // slightly heavier diagonal then makes one that still preconditions well.
    const std::vector<OffPatternBlock>* blocks = coupling ? &coupling->blocks() : nullptr;
    bool factorized = false;
    for (const double shift : {0.0, 1e-8, 1e-4}) {
      factorized = factorize([&] { return s.cholesky.compute(A, s.additions, blocks, shift); });
      if (factorized) break;
    }
    if (factorized) {
      CgResult r = pcg(s.cholesky, max_cg);
      r.iterations += stale.iterations;
      return r;
    }
  }
  std::clock_t t0 = std::clock();
  s.block_jacobi.compute(A);
  report.seconds_preconditioner += processor_seconds_since(t0);
  CgResult r = pcg(s.block_jacobi, max_cg);
  r.iterations += stale.iterations;
  return r;
}

// Forces at the iterate: x = x(v), f = f(x, v, t_force).
void evaluate(const Model& model, const State& state, ImplicitSolver& s, const StepEquation& eq,
              ForcePlan& plan, int threads, const Vec3List& v, Vec3List& x, Vec3List& f) {
  positions(model, s.x_base, eq.beta, state.x, v, x);
  compute_forces(model, x, v, eq.t_force, f, plan, threads);
}

// End positions x_end_base + beta_end v, m.
const Vec3List& end_positions(const Model& model, ImplicitSolver& s, const StepEquation& eq,
                              const State& state, const Vec3List& v) {
  positions(model, s.x_end_base, eq.beta_end, state.x, v, s.x_end);
  return s.x_end;
}

// The line search's merit along v + alpha dv (docs/implicit.md), relative to alpha = 0.
class Merit {
 public:
  Merit(const Model& model, const State& state, ImplicitSolver& s, const StepEquation& eq,
        ForcePlan& plan, int threads)
      : model_(model), state_(state), s_(s), eq_(eq), plan_(plan), threads_(threads) {}

  // Prepares the merit at the iterate s.v (forces s.f there) along s.dv; returns its
  // slope at alpha = 0 (negative along a descent direction).
  double start(LineSearch kind) {
    kind_ = kind;
    const int n = model_.num_vertices();
    if (kind_ == LineSearch::Residual) {
      value0_ = residual_norm(model_, s_, eq_, s_.v, s_.f);
      return -value0_;
    }
    // Incremental potential: the kinetic part, the potential energy U (membrane, bending,
    // gravity) of x(v), and the non-conservative forces f_nc (damping, wind) frozen as
    // their linearization around the iterate: f_nc(v) + df_nc/dv (v' - v).
    compute_forces(model_, s_.x, s_.v, eq_.t_force, s_.f_conservative, plan_, threads_,
                   ForceTerms::Conservative);
    mass_dv_dv_ = 0.0;
    momentum_dv_ = 0.0;
    nonconservative_dv_ = 0.0;
    friction0_ = s_.contacts.friction_potential(s_.v) + s_.barrier.potential(s_.v);
    gravity_dv_ = 0.0;
    for (int i = 0; i < n; ++i) {
      if (model_.pinned[i]) continue;
      const Vec3 d = s_.dv.segment<3>(3 * i);
      mass_dv_dv_ += model_.mass[i] * d.squaredNorm();
      momentum_dv_ += model_.mass[i] * (s_.v[i] - s_.v_base[i]).dot(d);
      nonconservative_dv_ += (s_.f[i] - s_.f_conservative[i]).dot(d);
      if (model_.gravity) gravity_dv_ += model_.mass[i] * model_.gravity->dot(d);
    }
    // dv^T D dv of the damping matrix D = -df_nc/dv, from forces at (x, v + dv).
    s_.v_try = s_.v;
    for (int i = 0; i < n; ++i) {
      if (!model_.pinned[i]) s_.v_try[i] += s_.dv.segment<3>(3 * i);
    }
    compute_forces(model_, s_.x, s_.v_try, eq_.t_force, s_.f_probe, plan_, threads_);
    damping_dv_dv_ = 0.0;
    for (int i = 0; i < n; ++i) {
      if (!model_.pinned[i]) damping_dv_dv_ -= (s_.f_probe[i] - s_.f[i]).dot(s_.dv.segment<3>(3 * i));
    }
    triangle_energies(model_, s_.x, s_.triangle_energy);
    bending0_ = model_.bending ? bending_energy(*model_.bending, s_.x) : 0.0;
    value0_ = 0.0;
    // The slope is -rhs(v) . dv, with rhs = -g(v) plus the friction impulses F(v), whose
    // potential the merit holds.
    step_rhs(model_, s_, eq_, s_.v, s_.f, s_.reaction);
    return -s_.reaction.dot(s_.dv);
  }

  // The merit at v + alpha dv, with x_try, v_try, f_try left at that point (f_try only for
  // the residual merit; the caller evaluates forces for the accepted point).
  double at(double alpha) {
    const int n = model_.num_vertices();
    s_.v_try = s_.v;
    for (int i = 0; i < n; ++i) {
      if (!model_.pinned[i]) s_.v_try[i] += alpha * s_.dv.segment<3>(3 * i);
    }
    positions(model_, s_.x_base, eq_.beta, state_.x, s_.v_try, s_.x_try);
    if (kind_ == LineSearch::Residual) {
      compute_forces(model_, s_.x_try, s_.v_try, eq_.t_force, s_.f_try, plan_, threads_);
      return residual_norm(model_, s_, eq_, s_.v_try, s_.f_try);
    }
    const double kinetic = alpha * momentum_dv_ + 0.5 * alpha * alpha * mass_dv_dv_;
    double potential = membrane_energy_change(model_, s_.x_try, s_.triangle_energy) -
                       eq_.beta * alpha * gravity_dv_;
    if (model_.bending) potential += bending_energy(*model_.bending, s_.x_try) - bending0_;
    const double frozen = -eq_.beta * alpha * nonconservative_dv_ +
                          0.5 * eq_.beta * alpha * alpha * damping_dv_dv_;
    // Friction's potentials and the barrier's energy (+infinity past an obstacle).
    const double friction =
        s_.contacts.friction_potential(s_.v_try) + s_.barrier.potential(s_.v_try) - friction0_;
    return kinetic + potential + frozen + friction;
  }

  double value0() const { return value0_; }

 private:
  const Model& model_;
  const State& state_;
  ImplicitSolver& s_;
  const StepEquation& eq_;
  ForcePlan& plan_;
  const int threads_;
  LineSearch kind_ = LineSearch::Potential;
  double value0_ = 0.0;
  double mass_dv_dv_ = 0.0, momentum_dv_ = 0.0, nonconservative_dv_ = 0.0;
  double gravity_dv_ = 0.0, damping_dv_dv_ = 0.0, bending0_ = 0.0, friction0_ = 0.0;
};

// Newton's method on g(v) = 0 from v = v_n (already in s.v). Iteration k solves
//   (M - beta df/dv - beta^2 df/dx) dv = M (v_base - v) + beta f(x_lin, v)
//                                        + beta df/dx (x(v) - x_lin)
// with the Jacobians at (x_lin, v): the first iteration linearizes at the start of the step,
// x_lin = x_n (Baraff & Witkin 1998, eq. 16 for backward Euler), later ones at the iterate,
// x_lin = x(v), where the right-hand side is -g(v). PCG solves it with the contacts'
// constrained directions filtered out. Between iterations the contacts are updated (an
// active-set Newton method): released where they pull, switched from stick to slide,
// added where the iterate would end inside an obstacle. A backtracking line search on the
// merit (incremental potential or residual) picks each step length. Newton stops when the
// residual is below newton_tolerance times the initial one (or, with newton_motion_tolerance,
// the step moved no end position by more than that) after a whole step that changed no
// contact, or after max_newton_iterations iterations if the last was such a step, or after
// kExtraNewtonIterations more; a switch from stick to slide extends both limits.
void newton_solve(const Model& model, const State& state, Workspace& ws, ImplicitSolver& s,
                  const StepEquation& eq) {
  const int n = model.num_vertices();
  const ImplicitOptions& opt = model.implicit;
  const int threads = force_threads(ws.threads, model);
  s.cg.threads = threads;
  ForcePlan& plan = scratch_of(ws).forces;
  ImplicitReport& report = s.report;
  {
    // Reset, keeping the per-iteration vectors' capacity.
    ImplicitReport fresh;
    auto keep = [](auto& kept, auto& reused) {
      std::swap(kept, reused);
      kept.clear();
    };
    keep(fresh.residuals, report.residuals);
    keep(fresh.step_lengths, report.step_lengths);
    keep(fresh.cg_per_iteration, report.cg_per_iteration);
    keep(fresh.velocity_changes, report.velocity_changes);
    keep(fresh.feasible_lengths, report.feasible_lengths);
    keep(fresh.barrier_contacts, report.barrier_contacts);
    keep(fresh.merit_changes, report.merit_changes);
    report = std::move(fresh);
  }

  // CG measures residuals in the same M^-1 norm as Newton; pinned entries weigh nothing.
  int free_dofs = 0;
  s.weights.resize(3 * n);
  for (int i = 0; i < n; ++i) {
    free_dofs += model.pinned[i] ? 0 : 3;
    const double w = model.pinned[i] ? 0.0 : (model.mass[i] > 0.0 ? 1.0 / model.mass[i] : 1.0);
    s.weights.segment<3>(3 * i).setConstant(w);
  }
  const int max_cg = std::max(50, free_dofs);

  // Impulses given to the step (see substep): the step's affine velocity moves by them.
  if (!s.kicks.empty()) {
    for (int i = 0; i < n; ++i) {
      s.v_base[i] += eq.warm_scale * s.kicks[i];
      s.v[i] += eq.warm_scale * s.kicks[i];
    }
  }

  // Contacts at the start: vertices whose predicted end position (velocities unchanged)
  // is near or inside an obstacle.
  std::clock_t t0 = std::clock();
  s.contacts.clear(n);
  s.placed.clear();
  // With the barrier model the barrier takes every obstacle (a mesh's corners and edges
  // too) and the solve starts from end positions outside them; otherwise they are
  // constraints.
  s.barrier.begin(model, state.x, s.x_end_base, eq.beta, eq.beta_end, eq.t, eq.t_end);
  for (const Obstacle& ob : model.obstacles) {
    if (s.barrier.takes_obstacles()) break;
    s.placed.push_back(place_obstacle(ob, eq.t_end));
  }
  // The barrier's guess needs the forces at x_n where a vertex ends near an obstacle.
  s.barrier.make_feasible(s.v, s.v_base, [&]() -> const Vec3List& {
    compute_forces(model, state.x, s.v, eq.t_force, s.f_lin, plan, threads);
    return s.f_lin;
  });
  s.barrier.freeze_damping(s.v, state.v);
  if (!s.placed.empty()) {
    const Vec3List& x_end = end_positions(model, s, eq, state, s.v);
    // A vertex in contact at the end of the last step (and not released) is caught again
    // while its predicted gap is within the distance gravity moves it over the step.
    const double fall = model.gravity ? model.gravity->norm() * eq.beta_end * eq.beta_end : 0.0;
    s.contacts.detect(model, s.placed, x_end, kPenetrationTolerance, fall, &s.v, eq.beta,
                      eq.warm_scale);
    s.contacts.set_targets(s.x_end_base, eq.beta_end);
    s.contacts.project(s.v);
  }
  report.seconds_contact += processor_seconds_since(t0);

  // Residual at the initial guess.
  t0 = std::clock();
  evaluate(model, state, s, eq, plan, threads, s.v, s.x, s.f);
  double r = residual_norm(model, s, eq, s.v, s.f);
  report.seconds_residual += processor_seconds_since(t0);
  const double r0 = r;
  report.initial_residual = r0;
  report.residuals.push_back(r);
  // The tolerance is relative to the initial residual, or to the residual gravity alone
  // would leave over the step (beta |g| sqrt(sum m)) where that is larger: a cloth at rest
  // starts with a residual near zero that one iteration cannot shrink by the tolerance.
  const double gravity_residual =
      model.gravity ? eq.beta * model.gravity->norm() * std::sqrt(free_mass(model)) : 0.0;
  const double target = opt.newton_tolerance * std::max(r0, gravity_residual);
  // A guess taken without any solve must be that much closer again: accepted at the
  // target, a slow steady state (a fall at terminal speed, a sheet settling) would stay
  // short of its equilibrium by the whole tolerance, step after step.
  report.converged = (r <= opt.newton_tolerance * target);

  // Newton stops at iteration_limit, or at settled_limit after a settled iteration; a
  // switch of modes moves both on, up to `most`.
  const int most = kSwitchedNewtonFactor * (opt.max_newton_iterations + kExtraNewtonIterations);
  int iteration_limit = opt.max_newton_iterations + kExtraNewtonIterations;
  int settled_limit = opt.max_newton_iterations;
  bool settled = true;  // the last iteration took a whole step and changed no contact
  for (int k = 0; free_dofs > 0; ++k) {
    // Converged, once the contacts (or the barrier) have been checked by a solve.
    if (report.converged && settled && (k > 0 || (s.contacts.empty() && !s.barrier.enabled()))) {
      break;
    }
    if (k >= iteration_limit || (k >= settled_limit && settled)) break;
    const double r_start = r;
    // The system matrix at the linearization point.
    t0 = std::clock();
    const Vec3List& x_lin = k == 0 ? state.x : s.x;
    s.system.assemble(model, x_lin, s.v, eq.t_force, eq.beta, /*project_psd=*/true, threads);
    report.seconds_jacobian += processor_seconds_since(t0);

    // The direction. The first solve of a step starts from the previous step's velocity
    // change (consecutive steps change velocities alike), later ones from 0.
    t0 = std::clock();
    if (k == 0) {
      first_rhs(model, state, s, eq, plan, threads);
    } else {
      step_rhs(model, s, eq, s.v, s.f, s.rhs);
    }
    report.seconds_residual += processor_seconds_since(t0);
    s.contacts.add_friction_jacobian(s.v, s.system);
    s.barrier.add_hessian(s.v, s.system);
    s.dv.setZero(3 * n);
    if (k == 0 && has_history(model, state, eq.h, eq.t)) {
      for (int i = 0; i < n; ++i) {
        if (model.pinned[i]) continue;
        s.dv.segment<3>(3 * i) = eq.warm_scale * (state.v[i] - state.previous.v[i]);
      }
    }
    const CgResult cg = linear_solve(opt, s, max_cg, report);
    report.newton_iterations += 1;
    report.linear_solves += 1;
    report.cg_iterations += cg.iterations;
    report.cg_per_iteration.push_back(cg.iterations);
    if (!cg.converged) report.cg_failed = true;

    // The contacts' impulses in this solve.
    int contact_changes = 0;
    if (!s.contacts.empty()) {
      t0 = std::clock();
      s.system.matrix().multiply(s.dv, s.reaction, threads);
      s.reaction -= s.rhs;
      s.contacts.update(s.reaction);
      report.seconds_contact += processor_seconds_since(t0);
    }

    // Backtracking line search: the first step length with sufficient decrease of the
    // merit, otherwise the one with the least merit below the start. A direction that
    // decreases it at no length tried is not taken: after the first iteration (linearized
    // at the start of the step) Newton goes on from the iterate, whose own direction
    // descends; a later one is taken whole, since a step without it would apply no force.
    t0 = std::clock();
    // The barrier's line search stops short of the first touch of an obstacle. (First: it
    // also finds the mesh pairs the merit takes, at its start as along the direction.)
    const double longest = s.barrier.largest_step(s.v, s.dv);
    Merit merit(model, state, s, eq, plan, threads);
    const double slope = merit.start(opt.line_search);
    const double base = merit.value0();

    double alpha = longest, best_alpha = 0.0, best = base, accepted = 0.0, taken = base;
    for (int trial = 0; trial <= kMaxHalvings; ++trial, alpha *= 0.5) {
      const double value = merit.at(alpha);
      const double bound = opt.line_search == LineSearch::Residual
                               ? (1.0 - kSufficientDecrease * alpha) * base
                               : base + kSufficientDecrease * alpha * slope;
      if (value <= bound) {
        accepted = alpha;
        taken = value;
        break;
      }
      if (value < best) {
        best = value;
        best_alpha = alpha;
      }
    }
    const bool descended = accepted > 0.0 || best_alpha > 0.0;
    if (accepted == 0.0) {
      report.line_search_failed = best_alpha == 0.0;
      accepted = best_alpha > 0.0 ? best_alpha : (k == 0 ? 0.0 : longest);
      taken = best;
    }
    double largest_change = 0.0;
    for (int i = 0; i < n; ++i) {
      if (model.pinned[i]) continue;
      const Vec3 change = accepted * s.dv.segment<3>(3 * i);
      s.v[i] += change;
      largest_change = std::max(largest_change, change.norm());
    }
    s.barrier.freeze_damping(s.v, state.v);
    report.step_lengths.push_back(accepted);
    report.velocity_changes.push_back(largest_change);
    report.feasible_lengths.push_back(longest);
    report.merit_changes.push_back(taken - base);
    if (s.barrier.enabled()) report.barrier_contacts.push_back(s.barrier.active(s.v));
    report.seconds_residual += processor_seconds_since(t0);

    // Vertices the new iterate puts inside an obstacle get contacts, and the iterate meets
    // every constraint.
    if (!s.placed.empty()) {
      t0 = std::clock();
      const Vec3List& x_end = end_positions(model, s, eq, state, s.v);
      const int added =
          s.contacts.detect(model, s.placed, x_end, -kPenetrationTolerance, 0.0, &s.v, eq.beta,
                            eq.warm_scale);
      contact_changes += added;
      if (added > 0) {
        s.contacts.set_targets(s.x_end_base, eq.beta_end);
        s.contacts.project(s.v);
      }
      report.seconds_contact += processor_seconds_since(t0);
    }
    if (contact_changes > 0) report.contact_changes += 1;

    t0 = std::clock();
    evaluate(model, state, s, eq, plan, threads, s.v, s.x, s.f);
    r = residual_norm(model, s, eq, s.v, s.f);
    report.seconds_residual += processor_seconds_since(t0);
    report.residuals.push_back(r);
    // A step cut short (but taken) from an iterate as close as a guess must be to pass
    // unsolved settles too: there the merit's changes are rounding (a sheet at rest on the
    // barrier: 1e-19 J), which no whole step can be told to decrease.
    settled = (accepted == 1.0 || (accepted > 0.0 && r_start <= opt.newton_tolerance * target)) &&
              contact_changes == 0;
    // The residual rule, or (newton_motion_tolerance) a whole step that moved every end
    // position by less than the tolerance: the next would move them by far less.
    const bool small_motion = settled && opt.newton_motion_tolerance > 0.0 &&
                              largest_change * eq.beta_end <= opt.newton_motion_tolerance;
    report.converged = small_motion || r <= target;
    // After a whole step on these contacts (its CG converged, its line search descended):
    // sticking ones the friction cone cannot hold slide, and Newton goes on, while a solve
    // with the new modes can follow. Judged at every such step, not only once converged: a
    // stick beyond its cone holds the cloth behind it while Newton works against it, and
    // the cloth it frees may in turn need to slide (a sheet pushed over a floor by a wall
    // frees row after row).
    if (settled && cg.converged && descended && k + 1 < most &&
        s.contacts.switch_modes(report.converged) > 0) {
      report.contact_changes += 1;
      settled_limit = std::min(std::max(settled_limit, k + 1 + kIterationsAfterSwitch), most);
      iteration_limit =
          std::min(std::max(iteration_limit, settled_limit + kExtraNewtonIterations), most);
      settled = false;
      t0 = std::clock();
      r = residual_norm(model, s, eq, s.v, s.f);
      report.seconds_residual += processor_seconds_since(t0);
      report.converged = (r <= target);
    }
  }
  report.final_residual = r;
  report.contacts = s.contacts.size() + s.barrier.active(s.v, nullptr, &report.barrier_pairs);

  report.stuck_contacts = s.contacts.stuck();
  s.contacts.remember(s.v, release_impulses(model, eq, s), eq.beta);
  s.barrier.remember_landings(s.v);

  // Vertices the passes left inside an obstacle (the step's collision stage moves them out).
  if (!s.placed.empty()) {
    const Vec3List& x_end = end_positions(model, s, eq, state, s.v);
    for (int i = 0; i < n; ++i) {
      if (model.pinned[i] || s.contacts.contact_of(i) >= 0) continue;
      for (const PlacedObstacle& p : s.placed) {
        if (p.closest(x_end[i]).distance < -kPenetrationTolerance) {
          report.unresolved_contacts += 1;
          break;
        }
      }
    }
  }
  ws.newton_iterations = report.newton_iterations;
  ws.cg_iterations = report.cg_iterations;
  ws.factorizations = report.factorizations;
  ws.barrier_pairs = report.barrier_pairs;
}

ImplicitSolver& solver_of(Workspace& ws) {
  StepScratch& scratch = scratch_of(ws);
  if (!scratch.implicit) scratch.implicit = std::make_shared<ImplicitSolver>();
  return *scratch.implicit;
}

// Saves x_n, v_n before the step; afterwards they become State::previous.
void begin_step(const Model& model, const State& state, ImplicitSolver& s) {
  const size_t n = static_cast<size_t>(model.num_vertices());
  s.f.resize(n);
  s.f_try.resize(n);
  s.x_saved = state.x;
  s.v_saved = state.v;
}

void end_step(State& state, ImplicitSolver& s, double h, double t) {
  std::swap(state.previous.x, s.x_saved);
  std::swap(state.previous.v, s.v_saved);
  state.previous.t = t;
  state.previous.dt = h;
}

// The new state of backward Euler and BDF-2, whose unknown is v_{n+1}.
void take_velocities(const Model& model, const ImplicitSolver& s, State& state) {
  for (int i = 0; i < model.num_vertices(); ++i) {
    if (model.pinned[i]) continue;
    state.v[i] = s.v[i];
    state.x[i] = s.x[i];
  }
}

// The midpoint rule's end velocity v of a held contact with friction (see
// stop_held_contacts): friction only slows a vertex down, but 2 w - v_n counts w's
// friction twice, which sends a vertex that friction stopped in mid-step back along its
// path (and the next step's smoothed friction stops it only to about the sticking speed,
// so it slides to and fro). A sticking contact ends the step moving with the surface; a
// sliding one whose end velocity along w's sliding direction (relative to the surface)
// was reversed by that friction ends with none in that direction.
void stop_by_friction(const Model& model, const ImplicitSolver& s, const VertexContact& c,
                      Vec3& v) {
  const SlidingFriction friction = friction_of(c);
  const Vec3 slide_end = friction.sliding(v);  // m/s
  if (c.mode == ContactMode::Stick) {
    v -= slide_end;
    return;
  }
  const Vec3& w = s.v[c.vertex];
  const Vec3 slide_step = friction.sliding(w);  // m/s
  const double speed = slide_step.norm();
  if (speed == 0.0) return;
  const Vec3 along = slide_step / speed;
  const double end = slide_end.dot(along);  // m/s
  // What w's friction takes off the velocity along `along` over the whole step, m/s.
  const double braking = -2.0 * model.inv_mass[c.vertex] * friction.impulse(w).dot(along);
  if (end < 0.0 && end + braking > 0.0) v -= end * along;
}

// Contact is inelastic: a vertex whose contact held at the end of the step (it pushed, or
// pulled less than its release impulse) moves with the surface along the normal. Backward
// Euler's constraint gives that by itself from the step after landing on; BDF-2's base
// still holds the fall (4/3 x_n - 1/3 x_{n-1} lies beyond the plane at a landing, so its
// constraint throws the vertex back at about half its impact speed), and the midpoint
// rule's 2 w - v_n reflects it. So the relative normal velocity of a held contact is set
// to 0; with `history` (BDF-2) the normal part of x_n, v_n, the next step's history, is
// set to that of a vertex that moved at v_{n+1} over the step, so that the next step's
// base lies on the plane too; for a vertex caught with an impact still to absorb, the
// whole history is (its base would carry the sliding speed the impact's friction took off
// into the next steps). With `friction_stops` (the midpoint rule) friction's reflection is
// undone too (stop_by_friction).
void stop_held_contacts(const Model& model, const ImplicitSolver& s, State& state,
                        bool friction_stops, Vec3List* history_x, Vec3List* history_v,
                        double h) {
  const std::vector<VertexContact>& contacts = s.contacts.contacts();
  for (size_t k = 0; k < contacts.size(); ++k) {
    const VertexContact& c = contacts[k];
    const int i = c.vertex;
    if (c.pull > s.release[i]) continue;
    // A corner's other contact, if it held too: both are met together, with the first.
    const int first = s.contacts.contact_of(i), second = s.contacts.second_contact_of(i);
    const VertexContact* other =
        second < 0 ? nullptr : &contacts[static_cast<int>(k) == first ? second : first];
    if (other && other->pull > s.release[i]) other = nullptr;
    if (other && static_cast<int>(k) == second) continue;
    Vec3& v = state.v[i];
    if (other) {
      v -= along_two_normals(c.normal, other->normal, c.normal.dot(v - c.surface_velocity),
                             other->normal.dot(v - other->surface_velocity));
    } else {
      v -= c.normal.dot(v - c.surface_velocity) * c.normal;
    }
    if (friction_stops && c.friction > 0.0 && !other) stop_by_friction(model, s, c, v);
    if (!history_x) continue;
    const Vec3 x_before = state.x[i] - h * v;
    const Vec3 moved = x_before - (*history_x)[i], turned = v - (*history_v)[i];
    if (other) {
      (*history_x)[i] += along_two_normals(c.normal, other->normal, c.normal.dot(moved),
                                           other->normal.dot(moved));
      (*history_v)[i] += along_two_normals(c.normal, other->normal, c.normal.dot(turned),
                                           other->normal.dot(turned));
    } else if (c.unabsorbed_impact > 0.0) {
      (*history_x)[i] = x_before;
      (*history_v)[i] = v;
    } else {
      (*history_x)[i] += c.normal.dot(moved) * c.normal;
      (*history_v)[i] += c.normal.dot(turned) * c.normal;
    }
  }
}

// Backward Euler in velocity form: x_base = x_n, v_base = v_n, beta = h.
void backward_euler_stage(const Model& model, State& state, Workspace& ws, ImplicitSolver& s,
                          double h, double t) {
  s.x_base = state.x;
  s.v_base = state.v;
  s.x_end_base = state.x;
  s.v = state.v;
  newton_solve(model, state, ws, s, StepEquation{h, t, h, t + h, h, t + h, 1.0});
  take_velocities(model, s, state);
}

// Eq. 11 of the paper, v_{n+1} = v_n + h M^-1 f(x_{n+1}, v_{n+1}), x_{n+1} = x_n + h v_{n+1}.
void backward_euler_step(const Model& model, State& state, Workspace& ws, double h, double t) {
  ImplicitSolver& s = solver_of(ws);
  begin_step(model, state, s);
  backward_euler_stage(model, state, ws, s, h, t);
  end_step(state, s, h, t);
}

// BDF-2: x_{n+1} = 4/3 x_n - 1/3 x_{n-1} + 2/3 h v_{n+1},
//        v_{n+1} = 4/3 v_n - 1/3 v_{n-1} + 2/3 h M^-1 f(x_{n+1}, v_{n+1}).
// Started (and restarted whenever the state's history is not the step before, of the same
// size) by one backward Euler step.
void bdf2_step(const Model& model, State& state, Workspace& ws, double h, double t) {
  ImplicitSolver& s = solver_of(ws);
  const int n = model.num_vertices();
  const bool history = has_history(model, state, h, t);
  begin_step(model, state, s);
  if (!history) {
    backward_euler_stage(model, state, ws, s, h, t);
  } else {
    const StepHistory& previous = state.previous;
    s.x_base.resize(n);
    s.v_base.resize(n);
    for (int i = 0; i < n; ++i) {
      s.x_base[i] = (4.0 / 3.0) * state.x[i] - (1.0 / 3.0) * previous.x[i];
      s.v_base[i] = (4.0 / 3.0) * state.v[i] - (1.0 / 3.0) * previous.v[i];
    }
    s.x_end_base = s.x_base;
    s.v = state.v;
    const double beta = 2.0 * h / 3.0;
    newton_solve(model, state, ws, s, StepEquation{h, t, beta, t + h, beta, t + h, 1.0});
    take_velocities(model, s, state);
  }
  s.contacts.settle_stopped_normal(model, state.v, history ? 2.0 * h / 3.0 : h, 1.0,
                                   /*whole=*/false);
  stop_held_contacts(model, s, state, /*friction_stops=*/false, &s.x_saved, &s.v_saved, h);
  end_step(state, s, h, t);
}

// Implicit midpoint: v_{n+1} = v_n + h M^-1 f((x_n + x_{n+1})/2, (v_n + v_{n+1})/2),
// x_{n+1} = x_n + h (v_n + v_{n+1})/2. With the midpoint velocity w = (v_n + v_{n+1})/2
// this is a backward Euler step of h/2 for w: M (w - v_n) = h/2 f(x_n + h/2 w, w); the
// step ends at x_n + h w. A vertex in contact keeps no velocity into its obstacle, nor one
// that friction stopped (stop_held_contacts): the rule's reflection 2 w - v_n would bounce
// it off, or send it back.
void midpoint_solve(const Model& model, State& state, Workspace& ws, double h, double t) {
  ImplicitSolver& s = solver_of(ws);
  begin_step(model, state, s);
  s.x_base = state.x;
  s.v_base = state.v;
  s.x_end_base = state.x;
  s.v = state.v;
  newton_solve(model, state, ws, s, StepEquation{h, t, 0.5 * h, t + 0.5 * h, h, t + h, 0.5});
  for (int i = 0; i < model.num_vertices(); ++i) {
    if (model.pinned[i]) continue;
    state.x[i] += h * s.v[i];
    state.v[i] = 2.0 * s.v[i] - state.v[i];
  }
  s.contacts.settle_stopped_normal(model, state.v, 0.5 * h, 0.5, /*whole=*/true);
  s.contacts.stop_approach(state.v);
  stop_held_contacts(model, s, state, /*friction_stops=*/true, nullptr, nullptr, h);
  end_step(state, s, h, t);
}

// Newton, CG and factorization counts of the solves a step made, summed over the solves a
// step takes again (substeps, the collision stage's rounds, halved midpoint steps).
struct SolveCounts {
  int newton = 0, cg = 0, factorizations = 0;
  void add(const Workspace& ws) {
    newton += ws.newton_iterations;
    cg += ws.cg_iterations;
    factorizations += ws.factorizations;
  }
  void store(Workspace& ws) const {
    ws.newton_iterations = newton;
    ws.cg_iterations = cg;
    ws.factorizations = factorizations;
  }
};

// The midpoint rule conserves energy only where the forces are linear over a step. With the
// barrier, a midpoint step longer than about 1/240 s that stops part of a falling cotton
// sheet at an obstacle ends with several times the elastic energy its solve saw: the rule
// weighs the membrane at the midpoint, half way to a stretch the barrier makes at the end
// (measured: 0.21 J gained at 1/60 s on a 0.6 m sheet, 0.05 J at 1/120 s, none at 1/240 s;
// docs/implicit.md). Held by the constraints, the same sheet gained 0.05-0.12 J at every step
// from 1/240 to 1/30 s, the demo diverged at 1/240 s, and without contact a hanging sheet
// gains energy at 1/64 s (docs/accuracy.md).
// So a midpoint step that raises the total energy (the barrier's included) by more than the
// work the wind and moving obstacles did over it, plus kEnergyRuleSlack of the energy at
// stake (kinetic, elastic and barrier energy, that work, plus the weight over dhat), is
// taken again as two halves, at most kMaxEnergyRuleHalvings deep. (Not with the collision
// stage's impulses, which each half would take whole.) BDF-2 steps are held by the same
// rule: BDF-2 is not energy-stable in contact either, and a cotton sheet dropped on a sphere
// with the constraints at 1/30 s gained 0.012 and 0.043 J in two steps where its hanging
// sides met the ground. Its halves restart it with a backward Euler step, and so does the
// next step, whose history is then of half its length (see ruled_bdf2_step for wind).
constexpr double kEnergyRuleSlack = 1e-4;
constexpr int kMaxEnergyRuleHalvings = 4;

// The midpoint positions (x0 + x1) / 2 (m) and velocities (x1 - x0) / h (m/s) of a step of
// length h from x0 to x1.
void midpoint_path(const Vec3List& x0, const Vec3List& x1, double h, Vec3List& x_mid,
                   Vec3List& w) {
  x_mid.resize(x0.size());
  w.resize(x0.size());
  for (size_t i = 0; i < x0.size(); ++i) {
    x_mid[i] = 0.5 * (x0[i] + x1[i]);
    w[i] = (x1[i] - x0[i]) / h;
  }
}

// The wind's work over a midpoint step from x0 to x1 (m) whose midpoint positions and
// velocities are x_mid and w at time t_mid, J: the step's own wind force there times the
// displacement. It is the wind's share of the step's change of kinetic energy.
double midpoint_wind_work(const Model& model, const Vec3List& x0, const Vec3List& x1,
                          const Vec3List& x_mid, const Vec3List& w, double t_mid, Vec3List& f) {
  f.assign(x0.size(), Vec3::Zero());
  add_wind(model, *model.wind, x_mid, w, t_mid, 0, model.num_triangles(), VertexForces::of(f));
  double work = 0.0;
  for (int i = 0; i < model.num_vertices(); ++i) {
    if (!model.pinned[i]) work += f[i].dot(x1[i] - x0[i]);
  }
  return work;
}

// The work the obstacles' contacts do over a midpoint step of length h from `start`, with
// midpoint positions x_mid (m) and velocities w (m/s) at time t_mid, J. A free vertex's
// contact impulse (constraint and friction) follows from the step's momentum balance:
// M (v_{n+1} - v_n) = h f(x_mid, w) + J with v_{n+1} = 2 w - v_n, so
// J = 2 M (w - v_n) - h f(x_mid, w); its work is J . w, w = (x_{n+1} - x_n) / h.
double midpoint_contact_work(const Model& model, const State& start, const Vec3List& x_mid,
                             const Vec3List& w, double h, double t_mid, Workspace& ws,
                             Vec3List& f) {
  compute_forces(model, x_mid, w, t_mid, f, ws);
  double work = 0.0;
  for (int i = 0; i < model.num_vertices(); ++i) {
    if (model.pinned[i]) continue;
    const Vec3 impulse = 2.0 * model.mass[i] * (w[i] - start.v[i]) - h * f[i];  // kg*m/s
    work += impulse.dot(w[i]);
  }
  return work;
}

// The work obstacles moving over a step of length h from `start` at t to `end` can do on
// the cloth through their contacts, J. A free vertex's contact impulse is what its forces
// do not explain, J = M (v_{n+1} - v_n) - h f, with f where the method takes it: at the
// end of the step, or the midpoint rule's at its midpoint (x_mid, w). In the obstacle's
// frame a contact only takes energy, so J . u bounds what it gives, u the velocity of the
// obstacle's surface; a correction that throws a vertex out faster than the surface moves
// is not counted. A vertex counts where its nearest obstacle moves and lies within `reach`
// (m) past its thickness: a mesh's vertex or edge pushes a cloth triangle, so reach is an
// edge of the cloth.
double moving_contact_work(const Model& model, const State& start, const State& end,
                           const Vec3List& x_mid, const Vec3List& w, double h, double t,
                           double reach, Workspace& ws, Vec3List& f) {
  std::vector<PlacedObstacle> moving, still;
  for (const Obstacle& ob : model.obstacles) {
    (ob.motion.moves_between(t, t + h) ? moving : still).push_back(place_obstacle(ob, t + h));
  }
  if (model.integrator == Integrator::ImplicitMidpoint) {
    compute_forces(model, x_mid, w, t + 0.5 * h, f, ws);
  } else {
    compute_forces(model, end.x, end.v, t + h, f, ws);
  }
  double work = 0.0;
  for (int i = 0; i < model.num_vertices(); ++i) {
    if (model.pinned[i]) continue;
    double nearest = INFINITY;  // m, past the thickness
    Vec3 surface_velocity = Vec3::Zero();  // m/s
    for (const PlacedObstacle& ob : moving) {
      const double band = ob.obstacle->thickness + reach;  // m
      const SurfacePoint p = ob.closest(end.x[i], band);
      const double gap = p.distance - ob.obstacle->thickness;
      if (p.distance < band && gap < nearest) {
        nearest = gap;
        surface_velocity = p.velocity;
      }
    }
    if (nearest == INFINITY) continue;
    bool moving_nearest = true;
    for (const PlacedObstacle& ob : still) {
      const double band = ob.obstacle->thickness + nearest;  // m
      const double gap = ob.closest(end.x[i], band).distance - ob.obstacle->thickness;
      moving_nearest = moving_nearest && gap >= nearest;
    }
    if (!moving_nearest) continue;
    const Vec3 impulse = model.mass[i] * (end.v[i] - start.v[i]) - h * f[i];  // kg*m/s
    work += impulse.dot(surface_velocity);
  }
  return work;
}

// Where a rule estimates the work of moving obstacles' contacts from: the midpoint rule's
// own momentum balance, or (for any method) the impulses near the moving obstacles.
enum class ContactWork { MidpointRule, NearMovingObstacles };

// The energy balance of a step of length h from `start` at t to `end`, J: the energy at
// each end (kinetic, elastic, gravity's and the barrier's) and the work supplied over the
// step (the wind's along the straight path, and moving obstacles' through their contacts).
// The midpoint rule's estimate of those contacts' work takes every vertex's impulse, the
// barrier's included (its force is not among compute_forces' terms), so with it and a
// moving obstacle the barrier's energy stays out and its work is in. The estimate near
// moving obstacles takes only their contacts' work, and the barrier's energy stays in.
// Each rule adds the end's parts in its own order: another order can round differently.
struct EnergyBalance {
  double kinetic = 0.0, elastic = 0.0, barrier = 0.0;  // at the start
  double start_energy = 0.0;  // at the start: those and gravity's
  double end_energy = 0.0;    // at the end, all but the barrier's
  double end_barrier = 0.0;   // at the end, the barrier's
  double supplied = 0.0;      // over the step
};

EnergyBalance energy_balance(const Model& model, const State& start, const State& end, double h,
                             double t, Workspace& ws, ContactWork contact_work) {
  ImplicitSolver& s = solver_of(ws);
  const bool moving = has_moving_obstacle(model, t, t + h);
  // energy_of is 0 where the barrier takes nothing.
  const bool barrier = !(moving && contact_work == ContactWork::MidpointRule);
  EnergyBalance b;
  b.barrier = barrier ? s.barrier.energy_of(model, start.x, t) : 0.0;
  b.kinetic = kinetic_energy(model, start.v);
  b.elastic = elastic_energy(model, start.x);
  b.start_energy = b.kinetic + b.elastic + gravity_potential(model, start.x) + b.barrier;
  if (model.wind || moving) {
    const double t_mid = t + 0.5 * h;
    midpoint_path(start.x, end.x, h, s.work_x, s.work_v);
    if (model.wind) {
      b.supplied += midpoint_wind_work(model, start.x, end.x, s.work_x, s.work_v, t_mid, s.work_f);
    }
    if (moving && contact_work == ContactWork::MidpointRule) {
      b.supplied +=
          midpoint_contact_work(model, start, s.work_x, s.work_v, h, t_mid, ws, s.work_f);
    } else if (moving) {
      b.supplied += moving_contact_work(model, start, end, s.work_x, s.work_v, h, t,
                                        mean_rest_edge(model), ws, s.work_f);
    }
  }
  b.end_energy = total_energy(model, end);
  b.end_barrier = barrier ? s.barrier.energy_of(model, end.x, t + h) : 0.0;
  return b;
}

// A method's solve of one step of h from t.
using MethodSolve = void (*)(const Model&, State&, Workspace&, double, double);

// One step of h from t by `solve` under the energy rule above, its moving obstacles' work
// estimated as `work` says.
void energy_ruled_step(const Model& model, State& state, Workspace& ws, double h, double t,
                       MethodSolve solve, ContactWork work, int halvings = 0) {
  ImplicitSolver& s = solver_of(ws);
  const bool guard = s.kicks.empty() && halvings < kMaxEnergyRuleHalvings;
  if (!guard) {
    solve(model, state, ws, h, t);
    return;
  }
  const State start = state;
  const ContactMemory contacts = contact_memory(s);
  solve(model, state, ws, h, t);
  const EnergyBalance b = energy_balance(model, start, state, h, t, ws, work);
  const double at_stake = b.kinetic + b.elastic + b.barrier + std::abs(b.supplied) +
                          free_weight(model) * barrier_distance(model);  // J
  const double e1 = b.end_energy + b.end_barrier - b.supplied;  // J, less the supplied work
  if (e1 <= b.start_energy + kEnergyRuleSlack * at_stake) return;
  SolveCounts counts;  // the whole step's solve, discarded, and both halves'
  counts.add(ws);
  state = start;
  restore(s, contacts);
  energy_ruled_step(model, state, ws, 0.5 * h, t, solve, work, halvings + 1);
  counts.add(ws);
  energy_ruled_step(model, state, ws, 0.5 * h, t + 0.5 * h, solve, work, halvings + 1);
  counts.add(ws);
  counts.store(ws);
}

// A BDF-2 step, under the energy rule unless the scene has wind: the rule's estimate of
// the wind's work (its force at the midpoint times the displacement) is not BDF-2's, and
// a free sheet in a steady wind, which gains only the wind's work, was taken again.
void ruled_bdf2_step(const Model& model, State& state, Workspace& ws, double h, double t) {
  if (model.wind) {
    bdf2_step(model, state, ws, h, t);
  } else {
    energy_ruled_step(model, state, ws, h, t, bdf2_step, ContactWork::NearMovingObstacles);
  }
}

// A backward Euler step, under the energy rule unless the scene has wind (as BDF-2, for
// the same reason). An exact backward Euler step does not gain energy, but Newton stops
// at newton_tolerance (1e-2 of the starting residual by default), short of it: a
// 1000-triangle cotton sheet dropped on a sphere with the constraints at 1/30 s gained
// 0.2 J, 60% of its weight's work until then, in three steps that Newton ended at 0.4-0.9%
// of their starting residual.
void ruled_backward_euler_step(const Model& model, State& state, Workspace& ws, double h,
                               double t) {
  if (model.wind) {
    backward_euler_step(model, state, ws, h, t);
  } else {
    energy_ruled_step(model, state, ws, h, t, backward_euler_step,
                      ContactWork::NearMovingObstacles);
  }
}

void method_step(const Model& model, State& state, Workspace& ws, double h, double t) {
  switch (model.integrator) {
    case Integrator::Bdf2:
      ruled_bdf2_step(model, state, ws, h, t);
      break;
    case Integrator::ImplicitMidpoint:
      energy_ruled_step(model, state, ws, h, t, midpoint_solve, ContactWork::MidpointRule);
      break;
    default:
      ruled_backward_euler_step(model, state, ws, h, t);
      break;
  }
}

}  // namespace

double moving_obstacles_work(const Model& model, const State& start, const State& end, double h,
                             Workspace& ws) {
  ImplicitSolver& s = solver_of(ws);
  midpoint_path(start.x, end.x, h, s.work_x, s.work_v);
  return moving_contact_work(model, start, end, s.work_x, s.work_v, h, start.t,
                             mean_rest_edge(model), ws, s.work_f);
}

const ImplicitReport& backward_euler(const Model& model, State& state, Workspace& ws) {
  ruled_backward_euler_step(model, state, ws, model.dt, state.t);
  return *last_implicit_report(ws);
}

const ImplicitReport& bdf2(const Model& model, State& state, Workspace& ws) {
  ruled_bdf2_step(model, state, ws, model.dt, state.t);
  return *last_implicit_report(ws);
}

const ImplicitReport& implicit_midpoint(const Model& model, State& state, Workspace& ws) {
  energy_ruled_step(model, state, ws, model.dt, state.t, midpoint_solve,
                    ContactWork::MidpointRule);
  return *last_implicit_report(ws);
}

namespace {

// The length a vertex may close on an obstacle per substep, twice over (m): a sphere's or
// cylinder's radius, a mesh's mean rest edge of the cloth (its parts may be thin); 0 for a
// plane, which no vertex passes without ending inside it.
double passing_size(const Obstacle& ob, double edge) {
  return ob.kind == ObstacleKind::Plane  ? 0.0
         : ob.kind == ObstacleKind::Mesh ? edge
                                         : ob.radius;
}

// For each obstacle, the largest approach speed (m/s) of the vertices that may reach it
// within the step (`speed`, 0: none), and of those that may pass it (`passing`): with the
// velocity gravity adds over the step, a vertex that would move farther than the obstacle's
// passing_size (a sheet let go at rest 0.1 m above a sphere of radius 0.25 m fell through
// it in one step of 0.25 s, which its start velocity did not foresee); not a vertex held
// where it rests (at the thickness, or within the barrier's distance), which the contact
// catches again. A moving obstacle is
// looked at where it starts the step as well as where it ends it: one that passes the cloth
// within the step is, at its end, moving away from the vertices it passed.
struct Approaches {
  std::vector<double> speed, passing;  // (obstacles) m/s
};

// edge: the cloth's mean rest edge, m.
Approaches approach_speeds(const Model& model, const State& state, double edge) {
  const double h = model.dt;
  const double fall = model.gravity ? 0.5 * model.gravity->norm() * h * h : 0.0;  // m
  const Vec3 gained = model.gravity ? Vec3(*model.gravity * h) : Vec3::Zero();     // m/s
  const double held =  // m: the gap where a vertex rests held by its contact
      1e-6 + (model.implicit.contact == ContactModel::Barrier ? barrier_distance(model) : 0.0);
  Approaches out;
  out.speed.assign(model.obstacles.size(), 0.0);
  out.passing.assign(model.obstacles.size(), 0.0);
  for (size_t o = 0; o < model.obstacles.size(); ++o) {
    const Obstacle& ob = model.obstacles[o];
    const double size = passing_size(ob, edge);  // m
    for (const double t : {state.t + h, state.t}) {
      const PlacedObstacle placed = place_obstacle(ob, t);
      for (int i = 0; i < model.num_vertices(); ++i) {
        if (model.pinned[i]) continue;
        const SurfacePoint p = placed.closest(state.x[i]);
        const Vec3 relative = state.v[i] - p.velocity;  // m/s
        const double approach = -p.normal.dot(relative);
        const double gap = p.distance - ob.thickness;  // m
        if (approach > 0.0 && gap < approach * h + fall) {
          out.speed[o] = std::max(out.speed[o], approach);
        }
        const double falling = -p.normal.dot(relative + gained);  // m/s, at the step's end
        if (size > 0.0 && falling * h > size && gap > held && gap < falling * h) {
          out.passing[o] = std::max(out.passing[o], falling);
        }
      }
      if (!ob.motion.moves()) break;
    }
  }
  return out;
}

int substeps_for(const Model& model, double rate) {
  const double substeps = std::ceil(model.dt * rate / kSubstepMotion);
  return static_cast<int>(std::clamp(substeps, 1.0, static_cast<double>(kMaxSubsteps)));
}

// The substeps implicit_substeps predicts, and the fewest that keep a vertex from passing
// an obstacle within one unseen: those that let a vertex that may reach a sphere or
// cylinder close at most kSubstepMotion of its radius on it per substep (a mesh obstacle:
// of a mean rest edge, its parts may be thin). A plane bounds a half-space that no vertex
// can pass without ending inside it.
struct SubstepNeeds {
  int predicted = 1;
  int passing = 1;
};

SubstepNeeds substep_needs(const Model& model, const State& state) {
  double rate = 0.0;  // 1/s: a speed relative to a length
  for (int k = 0; k < model.num_triangles(); ++k) {
    const Tri& tri = model.triangles[k];
    for (int e = 0; e < 3; ++e) {
      const int a = tri[e], b = tri[(e + 1) % 3];
      const double length = (state.x[a] - state.x[b]).norm();
      if (length > 0.0) rate = std::max(rate, (state.v[a] - state.v[b]).norm() / length);
    }
  }
  SubstepNeeds needs;
  if (model.obstacles.empty()) {
    needs.predicted = substeps_for(model, rate);
    return needs;
  }
  // Vertices that may reach an obstacle within the step, by their approach speed over the
  // mean rest edge; and for passing, over the obstacle's own size.
  const double edge = mean_rest_edge(model);
  const Approaches approaches = approach_speeds(model, state, edge);
  double passing = 0.0;  // 1/s
  for (size_t o = 0; o < model.obstacles.size(); ++o) {
    const double speed = approaches.speed[o];  // m/s
    if (speed > 0.0 && edge > 0.0) rate = std::max(rate, speed / edge);
    const double size = passing_size(model.obstacles[o], edge);  // m
    const double fastest = std::max(speed, approaches.passing[o]);
    if (size > 0.0) passing = std::max(passing, fastest / size);
  }
  needs.predicted = substeps_for(model, rate);
  needs.passing = substeps_for(model, passing);
  return needs;
}

}  // namespace

int implicit_substeps(const Model& model, const State& state) {
  return substep_needs(model, state).predicted;
}

double relative_motion(const Model& model, const Vec3List& x0, const Vec3List& x1) {
  double largest2 = 0.0;  // squared, edges^2
  for (const Tri& tri : model.triangles) {
    for (int e = 0; e < 3; ++e) {
      const int a = tri[e], b = tri[(e + 1) % 3];
      const Vec3 edge = x0[a] - x0[b];
      const double length2 = edge.squaredNorm();
      if (length2 == 0.0) continue;
      const double change2 = (x1[a] - x1[b] - edge).squaredNorm();
      largest2 = std::max(largest2, change2 / length2);
    }
  }
  return std::sqrt(largest2);
}

const ImplicitReport* last_implicit_report(const Workspace& ws) {
  return ws.scratch && ws.scratch->implicit ? &ws.scratch->implicit->report : nullptr;
}

// Rounds of impulses a substep may take, and the stage correction (a fraction of the
// contact thickness) below which its result stands.
constexpr int kMaxKickRounds = 3;
constexpr double kKickTolerance = 0.1;
// A round that leaves more than this share of the last round's largest correction is the
// last: the cloth around a pair of layers can be too stiff at this substep for the impulses
// to part them (on a folding sheet at 1/60 s a round cut the correction by 1-2%).
constexpr double kStalledRound = 0.75;

// The length contact corrections are measured against, m: the thinnest contact thickness
// the scene declares, or a tenth of a typical edge when it declares none.
double contact_length(const Model& model) {
  double area = 0.0;
  for (const TriangleRest& r : model.rest) area += r.area;
  const int T = std::max(1, model.num_triangles());
  double length = 0.1 * std::sqrt(4.0 / std::sqrt(3.0) * area / T);
  for (const Obstacle& o : model.obstacles) {
    if (o.thickness > 0.0) length = std::min(length, o.thickness);
  }
  if (model.self_collision && model.self_collision->thickness > 0.0) {
    length = std::min(length, model.self_collision->thickness);
  }
  return length;
}

// One substep of h from t, with the collision stage (cloth_contact.h) when the model needs
// it. The stage corrects velocities (and so positions) after a solve; applied alone to an
// implicit step of this size, its corrections (millimetres near an obstacle's edge) are
// answered by no other vertex and stretch the membrane, measured as spikes of elastic
// energy. So while the stage moves a position by more than kKickTolerance of the contact
// length, the substep is solved again from its start with the stage's velocity changes so
// far given as impulses, which the rest of the cloth answers within the solve, and the
// stage runs on that result (at most kMaxKickRounds times). The impulses are the stage's
// own (outward from obstacles, equal and opposite between layers), so the substep gains no
// momentum the stage did not give.
// The last round's corrections have no solve after them, and the stretch they leave can
// exceed what the stage took out of the motion: a fold of 600 triangles at 1/60 s went
// from 0.6 to 12 J with backward Euler and diverged with the midpoint rule
// (docs/implicit.md). So a substep that the stage corrected and that ends with more energy
// than it began with, the wind supplied and moving obstacles' contacts can supply
// (moving_contact_work) is taken again as two halves, at most kMaxStageHalvings deep: the
// gain falls with the substep's length (on that fold about 0.09, 0.03 and 0.007 J at 8, 4
// and 2 ms; none at 1 ms). Allowed: the energy rule's slack (kEnergyRuleSlack), and the
// work of lifting the sheet by the stage's tolerance.
constexpr int kMaxStageHalvings = 4;

void substep(const Model& model, State& state, Workspace& ws, ImplicitSolver& s, double h,
             double t, bool stage, int halvings = 0) {
  s.kicks.clear();
  if (!stage) {
    method_step(model, state, ws, h, t);
    return;
  }
  const State start = state;
  const ContactMemory contacts = contact_memory(s);
  bool corrected = false;
  method_step(model, state, ws, h, t);
  SolveCounts counts;
  counts.add(ws);
  s.kicks.assign(model.num_vertices(), Vec3::Zero());
  const double settled = kKickTolerance * contact_length(model);  // m
  // Each round solves with the impulses found so far; the stage's further corrections of
  // that solve are added to them, until the stage has little left to correct.
  double last = 0.0;  // m: the last round's largest correction
  for (int round = 0;; ++round) {
    const Vec3List solved = state.v;
    run_collision_stage(model, t, h, start.x, state, ws);
    double largest = 0.0;  // m: the stage's largest change of a position
    for (int i = 0; i < model.num_vertices(); ++i) {
      if (model.pinned[i]) continue;
      const Vec3 kick = state.v[i] - solved[i];
      s.kicks[i] += kick;
      largest = std::max(largest, h * kick.norm());
    }
    corrected = corrected || largest > 0.0;
    const bool stalled = round > 0 && largest > kStalledRound * last;
    if (largest <= settled || round == kMaxKickRounds || stalled) break;
    last = largest;
    state = start;
    restore(s, contacts);
    method_step(model, state, ws, h, t);
    counts.add(ws);
  }
  s.kicks.clear();
  double gain = 0.0, slack = 0.0;  // J: the substep's energy gain, and what it may gain
  const bool guard = corrected && halvings < kMaxStageHalvings;
  if (guard) {
    const EnergyBalance b =
        energy_balance(model, start, state, h, t, ws, ContactWork::NearMovingObstacles);
    gain = b.end_energy - b.supplied + b.end_barrier - b.start_energy;
    slack = kEnergyRuleSlack * (b.kinetic + b.elastic + std::abs(b.supplied)) +
            free_weight(model) * settled;
  }
  if (guard && gain > slack) {
    state = start;
    restore(s, contacts);
    // The gain falls about fourfold per halving (on the fold above): halve at once as
    // often as that needs, rather than trying each length in turn.
    int k = 1;
    for (double left = gain; left > 4.0 * slack && halvings + k < kMaxStageHalvings;
         left /= 4.0) {
      ++k;
    }
    const int pieces = 1 << k;
    for (int piece = 0; piece < pieces; ++piece) {
      substep(model, state, ws, s, h / pieces, t + piece * h / pieces, stage, halvings + k);
      counts.add(ws);
    }
  } else {
    s.stage_depth = std::max(s.stage_depth, halvings);
  }
  counts.store(ws);
}

// A substep whose Newton solve neither converged nor reduced the residual to
// kRetryReduction of its start is not kept: the step is taken again in twice as many
// substeps. In contact, solves that stop short of convergence have typically reduced their
// residual 20 to 100 times while friction modes kept switching; taking them all again cost
// the demo at 1/60 s 2.4 times the processor time for the same drape (docs/implicit.md).
// So where nothing in the scene supplies energy (no wind, no moving obstacle), a substep
// that reduced its residual to kLooseReduction is kept when it did not raise the total
// energy: it is then as trustworthy as a converged one by the measure that matters here
// (an unconverged step that gains energy at contact is taken again).
constexpr double kRetryReduction = 0.01;
constexpr double kLooseReduction = 0.1;

// Whether the substep just solved (report r) over [t0, t1] (s) from positions x0 and
// velocities v0 is kept.
// The energies are evaluated only for a substep that needs the energy rule.
bool keep_substep(const Model& model, const State& state, const ImplicitReport& r,
                  const Vec3List& x0, const Vec3List& v0, double t0, double t1) {
  if (r.converged || r.final_residual <= kRetryReduction * r.initial_residual) return true;
  if (r.final_residual > kLooseReduction * r.initial_residual ||
      supplies_energy(model, t0, t1)) {
    return false;
  }
  const double e_start =
      kinetic_energy(model, v0) + elastic_energy(model, x0) + gravity_potential(model, x0);
  return total_energy(model, state) <= e_start;
}

// The substeps a step is planned with, at most `predicted` (implicit_substeps): fewer when
// the motion the last step measured asks for fewer. The prediction reads every velocity as
// motion to come, the whole step long: at a landing it asked the demo for 5-7 substeps
// where one moved no vertex more than 0.8 of an edge relative to its neighbours (the
// contact stops the approach, and the solve damps velocities that flicker between
// neighbours). A step planned below the prediction is checked after each substep. The
// plan falls by half a step at most, and not in the step after one taken again: a longer
// substep can move more than its shorter pieces did together.
int planned_substeps(const ImplicitSolver& s, int predicted) {
  if (s.step_motion < 0.0) return predicted;
  const int measured = static_cast<int>(std::ceil(s.step_motion / kMotionLimit));
  const int lowest = s.step_retaken ? s.step_substeps : (s.step_substeps + 1) / 2;
  return std::clamp(std::max(measured, lowest), 1, predicted);
}

void integrate_implicit(const Model& model, State& state, Workspace& ws) {
  ImplicitSolver& s = solver_of(ws);
  const bool stage = needs_cloth_contact(model);
  const SubstepNeeds needs = substep_needs(model, state);
  const int predicted = needs.predicted;
  // The midpoint rule does not damp the sheet's stiff modes (|R(inf)| = 1): velocities
  // that flip from step to step stay, and a step planned below the prediction was taken
  // again so often on the hard scenes that it took 1.07-1.51 times the Newton iterations.
  const bool damped = model.integrator != Integrator::ImplicitMidpoint;
  // Never fewer than keep a vertex from passing an obstacle unseen: no check after the
  // substep could tell.
  const int planned = std::max(damped ? planned_substeps(s, predicted) : predicted,
                               needs.passing);
  // A step starts at no fewer substeps than the stage's energy rule needed in the last one,
  // so that it does not take again the long substeps that rule rejects while layers touch.
  const int stage_substeps = std::min(s.stage_substeps, kMaxSubsteps);
  int substeps = std::max(planned, stage_substeps);
  // A substep of a step planned below the prediction that moves a vertex more than
  // kMotionLimit of an edge relative to its neighbours sends the step back to the
  // prediction.
  bool checked = substeps < predicted;
  ws.planned_substeps = substeps;
  SolveCounts counts;
  double step_motion = 0.0;  // edges, summed over the kept substeps
  s.step_retaken = false;
  for (;;) {
    s.stage_depth = 0;
    const State start = state;
    const ContactMemory contacts = contact_memory(s);
    const double h = model.dt / substeps;
    const bool last_try = substeps >= kMaxSubsteps;
    ws.contact = ContactStats{};
    ws.contact_seconds = 0.0;
    bool kept = true;
    step_motion = 0.0;
    for (int k = 0; k < substeps && (kept || last_try); ++k) {
      s.x_substep = state.x;  // the substep's start, for the rules that judge it
      s.v_substep = state.v;
      substep(model, state, ws, s, h, state.t + k * h, stage);
      counts.add(ws);
      const double motion = relative_motion(model, s.x_substep, state.x);
      step_motion += motion;
      kept = kept && (!checked || motion <= kMotionLimit) &&
             keep_substep(model, state, s.report, s.x_substep, s.v_substep, state.t + k * h,
                          state.t + (k + 1) * h);
    }
    if (kept || last_try) break;
    state = start;
    restore(s, contacts);
    s.step_retaken = true;
    substeps = checked ? predicted : std::min(2 * substeps, kMaxSubsteps);
    checked = false;
  }
  s.step_motion = step_motion;
  s.step_substeps = substeps;
  counts.store(ws);
  ws.substeps = substeps;
  // Kept while the rule still halves; relaxed by half a step after a step it did not.
  s.stage_substeps = s.stage_depth > 0 ? substeps << s.stage_depth : s.stage_substeps / 2;
}

}  // namespace tissu
