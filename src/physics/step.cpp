#include "physics/step.h"

#include <cmath>
#include <sstream>

#include "physics/forces.h"
#include "physics/implicit.h"

namespace tissu {

// Eq. 9 (explicit Euler), eq. 10 (modified / symplectic Euler) and the paper's
// "calcul_vitesse_position" as printed (V += h F / (2 m), P += h V).
void integrate_explicit(const Model& model, State& state, Workspace& ws) {
  const double h = model.dt;
  compute_forces(model, state.x, state.v, state.t, ws.f);
  const int n = model.num_vertices();
  switch (model.integrator) {
    case Integrator::ExplicitEuler:
      for (int i = 0; i < n; ++i) {
        state.x[i] += h * state.v[i];
        state.v[i] += (h * model.inv_mass[i]) * ws.f[i];
      }
      break;
    case Integrator::SymplecticEuler:
      for (int i = 0; i < n; ++i) {
        state.v[i] += (h * model.inv_mass[i]) * ws.f[i];
        state.x[i] += h * state.v[i];
      }
      break;
    case Integrator::BenameurDjedi:
      for (int i = 0; i < n; ++i) {
        state.v[i] += (h * model.inv_mass[i] / 2.0) * ws.f[i];
        state.x[i] += h * state.v[i];
      }
      break;
    default:
      break;
  }
}

// Section 3, as printed: halve the displacement of a vertex up to n_it times while it is
// longer than the threshold; if the last measured displacement exceeded the threshold,
// recompute the velocity from the corrected displacement.
void apply_position_correction(const Model& model, const Vec3List& x_old, State& state) {
  const PositionCorrection& pc = *model.position_correction;
  const double h = model.dt;
  for (int i = 0; i < model.num_vertices(); ++i) {
    double dist = 0.0;
    for (int it = 0; it < pc.iterations; ++it) {
      const Vec3 diff = state.x[i] - x_old[i];
      dist = diff.norm();
      if (dist > pc.threshold) state.x[i] = x_old[i] + diff / 2.0;
    }
    if (dist > pc.threshold) state.v[i] = (state.x[i] - x_old[i]) / h;
  }
}

// Section 2.3 with the projection corrected (notes.md): a vertex inside an obstacle moves
// to the closest surface point; the inward normal velocity relative to the obstacle is
// removed and Coulomb friction slows the tangential velocity by mu * |removed normal part|.
void resolve_collisions(const Model& model, double t, Vec3List& x, Vec3List& v) {
  constexpr int kPasses = 4;  // overlapping obstacles: repeat until no vertex is inside
  for (int pass = 0; pass < kPasses; ++pass) {
    bool any_inside = false;
    for (const Obstacle& ob : model.obstacles) {
      const Vec3 ob_velocity = ob.velocity(t);
      for (int i = 0; i < model.num_vertices(); ++i) {
        if (model.pinned[i]) continue;
        Vec3 n;
        const double d = ob.signed_distance(x[i], t, &n);
        if (d >= 0.0) continue;
        any_inside = true;
        x[i] -= d * n;
        const Vec3 relative = v[i] - ob_velocity;
        const double vn = relative.dot(n);
        if (vn >= 0.0) continue;
        Vec3 tangential = relative - vn * n;
        const double vt = tangential.norm();
        const double slow = ob.friction * (-vn);
        tangential = (vt <= slow) ? Vec3::Zero() : Vec3(tangential * (1.0 - slow / vt));
        v[i] = ob_velocity + tangential;
      }
    }
    if (!any_inside) break;
  }
}

std::optional<Divergence> check_divergence(const Model& model, const State& state) {
  int fastest = -1;
  double top_speed2 = 0.0;
  for (int i = 0; i < model.num_vertices(); ++i) {
    const bool finite = state.x[i].allFinite();
    if (!finite || !state.v[i].allFinite()) {
      return Divergence{state.step, state.t, i,
                        finite ? "non-finite velocity" : "non-finite position"};
    }
    const double s2 = state.v[i].squaredNorm();
    if (s2 > top_speed2) {
      top_speed2 = s2;
      fastest = i;
    }
  }
  if (top_speed2 > model.max_speed * model.max_speed) {
    std::ostringstream reason;
    reason.precision(3);
    reason << "speed " << std::sqrt(top_speed2) << " m/s exceeds the limit of "
           << model.max_speed << " m/s";
    return Divergence{state.step, state.t, fastest, reason.str()};
  }
  return std::nullopt;
}

std::optional<Divergence> step(const Model& model, State& state, Workspace& ws) {
  const int n = model.num_vertices();
  ws.f.resize(n);
  if (model.position_correction) ws.x_old = state.x;

  switch (model.integrator) {
    case Integrator::ExplicitEuler:
    case Integrator::SymplecticEuler:
    case Integrator::BenameurDjedi:
      integrate_explicit(model, state, ws);
      break;
    case Integrator::BackwardEuler:
    case Integrator::Bdf2:
    case Integrator::ImplicitMidpoint:
      integrate_implicit(model, state, ws);
      break;
  }
  if (model.position_correction) apply_position_correction(model, ws.x_old, state);
  const double t_new = static_cast<double>(state.step + 1) * model.dt;
  if (!model.obstacles.empty()) resolve_collisions(model, t_new, state.x, state.v);
  state.step += 1;
  state.t = t_new;
  return check_divergence(model, state);
}

}  // namespace tissu
