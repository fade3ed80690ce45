#include "study/probe.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/error.h"
#include "physics/diagnostics.h"
#include "physics/stepper.h"

namespace tissu {

namespace {

std::string format_joules(double e) {
  std::ostringstream s;
  s.precision(3);
  s << e << " J";
  return s.str();
}

// The vertex moving fastest (the likely culprit of an energy blow-up).
int fastest_vertex(const State& state) {
  int best = 0;
  double top = -1.0;
  for (size_t i = 0; i < state.v.size(); ++i) {
    const double s2 = state.v[i].squaredNorm();
    if (s2 > top) {
      top = s2;
      best = static_cast<int>(i);
    }
  }
  return best;
}

// The vertex deepest inside an obstacle and its signed distance (m).
std::pair<int, double> deepest_vertex(const Model& model, const State& state) {
  std::pair<int, double> best{-1, INFINITY};
  for (const Obstacle& ob : model.obstacles) {
    for (int i = 0; i < model.num_vertices(); ++i) {
      Vec3 n;
      const double d = ob.signed_distance(state.x[i], state.t, &n);
      if (d < best.second) best = {i, d};
    }
  }
  return best;
}

}  // namespace

const char* probe_status_name(ProbeStatus status) {
  switch (status) {
    case ProbeStatus::Ok: return "ok";
    case ProbeStatus::Diverged: return "diverged";
    case ProbeStatus::EnergyUnbounded: return "energy_unbounded";
    case ProbeStatus::Penetration: return "penetration";
    case ProbeStatus::Interrupted: return "interrupted";
  }
  return "unknown";
}

double ProbeResult::wall_per_simulated_second() const {
  return simulated_time > 0.0 ? wall_seconds / simulated_time : 0.0;
}

double ProbeResult::cpu_per_simulated_second() const {
  return simulated_time > 0.0 ? cpu_seconds / simulated_time : 0.0;
}

std::vector<Integrator> all_integrators() {
  return {Integrator::ExplicitEuler, Integrator::SymplecticEuler, Integrator::BenameurDjedi,
          Integrator::BackwardEuler,  Integrator::Bdf2,            Integrator::ImplicitMidpoint};
}

Integrator parse_integrator_name(const std::string& name) {
  std::string list;
  for (Integrator i : all_integrators()) {
    if (name == integrator_name(i)) return i;
    list += (list.empty() ? "" : ", ") + std::string(integrator_name(i));
  }
  throw InputError("unknown integrator \"" + name + "\"; expected one of " + list);
}

ProbeResult run_probe(const Simulation& base, const ProbeSpec& spec) {
  if (!(spec.dt > 0.0) || !(spec.duration >= 0.0)) {
    throw InputError("probe: dt must be > 0 and duration >= 0");
  }
  Model model = base.model;
  model.integrator = spec.integrator;
  model.dt = spec.dt;
  State state = base.state;
  Stepper stepper(model, state);

  ProbeResult r;
  r.steps = spec.steps >= 0 ? spec.steps
                            : static_cast<long long>(std::ceil(spec.duration / spec.dt - 1e-9));
  const long long monitor_every =
      spec.monitor_every > 0 ? spec.monitor_every : std::max<long long>(1, r.steps / 256);
  const double eps = 1e-9 * spec.dt;  // time tolerance for "on the step grid", s

  const Energy e0 = measure_energy(model, state.x, state.v);
  r.energy_start = e0.total();
  r.energy_max = r.energy_start;
  r.energy_scale = energy_scale(model, state);
  r.energy_bound = r.energy_start + spec.energy_margin * r.energy_scale;
  if (!model.obstacles.empty()) r.min_clearance = min_clearance(model, state.x, state.t);

  std::vector<double> times = spec.sample_times;
  std::sort(times.begin(), times.end());
  size_t next = 0;
  const Vec3List& x_prev = stepper.before().x;  // the state before a step that crosses a
  const Vec3List& v_prev = stepper.before().v;  // sample time

  auto record_exact = [&](double t) {
    Sample s;
    s.time = t;
    s.x = state.x;
    s.energy = measure_energy(model, state.x, state.v);
    r.samples.push_back(std::move(s));
  };
  auto record_between = [&](double t, double t0) {
    const double a = (t - t0) / spec.dt;  // 0 at the previous step, 1 at this one
    Sample s;
    s.time = t;
    s.interpolated = true;
    s.x.resize(state.x.size());
    Vec3List v(state.v.size());
    for (size_t i = 0; i < state.x.size(); ++i) {
      s.x[i] = (1.0 - a) * x_prev[i] + a * state.x[i];
      v[i] = (1.0 - a) * v_prev[i] + a * state.v[i];
    }
    s.energy = measure_energy(model, s.x, v);
    r.samples.push_back(std::move(s));
  };

  // Monitoring: energy bound and obstacle penetration; returns false when unstable.
  auto monitor = [&]() -> bool {
    const double e = measure_energy(model, state.x, state.v).total();
    r.energy_max = std::max(r.energy_max, e);
    if (!(e <= r.energy_bound)) {
      r.status = ProbeStatus::EnergyUnbounded;
      r.failure = Divergence{state.step, state.t, fastest_vertex(state),
                             "total energy " + format_joules(e) + " exceeds the bound " +
                                 format_joules(r.energy_bound) + " (start " +
                                 format_joules(r.energy_start) + ")"};
      return false;
    }
    if (!model.obstacles.empty()) {
      const auto [vertex, depth] = deepest_vertex(model, state);
      r.min_clearance = std::min(*r.min_clearance, depth);
      if (depth < -spec.penetration_tolerance) {
        std::ostringstream reason;
        reason.precision(3);
        reason << "vertex " << depth * 1e3 << " mm inside an obstacle";
        r.status = ProbeStatus::Penetration;
        r.failure = Divergence{state.step, state.t, vertex, reason.str()};
        return false;
      }
    }
    return true;
  };

  if (spec.observe) spec.observe(state);
  for (long long s = 0;; ++s) {
    // Samples at this step's time.
    while (next < times.size() && times[next] <= state.t + eps) {
      if (std::fabs(times[next] - state.t) <= eps || s == 0) {
        record_exact(times[next]);
      } else {
        record_between(times[next], state.t - spec.dt);
      }
      ++next;
    }
    if (s == r.steps) {
      if (spec.monitored && s % monitor_every != 0) monitor();
      break;
    }
    if (spec.interrupted && spec.interrupted()) {
      r.status = ProbeStatus::Interrupted;
      break;
    }
    // Keep the state before a step that passes over a sample time, or that may diverge
    // when the run must end on its last good state.
    const std::optional<Divergence> divergence = stepper.advance(
        spec.keep_end || (next < times.size() && times[next] < state.t + spec.dt - eps));
    r.steps_done = s + 1;
    if (divergence) {
      r.status = ProbeStatus::Diverged;
      r.failure = divergence;
      if (spec.keep_end) stepper.restore_before();
      break;
    }
    if (spec.observe) spec.observe(state);
    if (spec.monitored && (s + 1) % monitor_every == 0 && !monitor()) break;
  }
  if (spec.keep_end) r.end = std::move(state);
  r.cpu_seconds = stepper.totals().cpu_seconds;
  r.wall_seconds = stepper.totals().wall_seconds;
  r.newton_iterations = stepper.totals().newton_iterations;
  r.cg_iterations = stepper.totals().cg_iterations;
  r.simulated_time = static_cast<double>(r.steps_done) * spec.dt;
  return r;
}

}  // namespace tissu
