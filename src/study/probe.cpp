#include "study/probe.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/error.h"
#include "physics/diagnostics.h"
#include "physics/run_driver.h"

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

namespace {

// What a probe does besides stepping: the samples at the requested times (with their
// energy), the caller's observer, and monitoring of the energy bound and obstacle clearance
// (a failure ends the run).
class ProbeObserver : public RunObserver {
 public:
  ProbeObserver(const Model& model, const ProbeSpec& spec, long long monitor_every,
                ProbeResult& r)
      : model_(model), spec_(spec), monitor_every_(monitor_every), r_(r),
        times_(spec.sample_times) {
    std::sort(times_.begin(), times_.end());
  }

  std::optional<double> next_sample_time() const override {
    if (next_ == times_.size()) return std::nullopt;
    return times_[next_];
  }
  void sample(const State& state, const SamplePoint& point) override {
    Sample s;
    s.time = point.time;
    s.interpolated = point.interpolated;
    s.x = state.x;
    s.energy = measure_energy(model_, state.x, state.v);
    r_.samples.push_back(std::move(s));
    ++next_;
  }
  void reached(const State& state, long long steps) override {
    if (spec_.observe) spec_.observe(state);
    if (steps > 0 && spec_.monitored && steps % monitor_every_ == 0) monitor(state);
  }
  bool wants_more() const override { return r_.status == ProbeStatus::Ok; }
  // The last step is always monitored.
  void finish(const State& state, const DriveResult& run) override {
    if (run.end == RunEnd::Completed && spec_.monitored && run.steps_done % monitor_every_ != 0) {
      monitor(state);
    }
  }

 private:
  // Energy bound and obstacle penetration; sets the status when unstable.
  void monitor(const State& state) {
    const double e = measure_energy(model_, state.x, state.v).total();
    r_.energy_max = std::max(r_.energy_max, e);
    if (!(e <= r_.energy_bound)) {
      r_.status = ProbeStatus::EnergyUnbounded;
      r_.failure = Divergence{state.step, state.t, fastest_vertex(state),
                              "total energy " + format_joules(e) + " exceeds the bound " +
                                  format_joules(r_.energy_bound) + " (start " +
                                  format_joules(r_.energy_start) + ")"};
      return;
    }
    if (!model_.obstacles.empty()) {
      const auto [vertex, depth] = deepest_vertex(model_, state);
      r_.min_clearance = std::min(*r_.min_clearance, depth);
      if (depth < -spec_.penetration_tolerance) {
        std::ostringstream reason;
        reason.precision(3);
        reason << "vertex " << depth * 1e3 << " mm inside an obstacle";
        r_.status = ProbeStatus::Penetration;
        r_.failure = Divergence{state.step, state.t, vertex, reason.str()};
      }
    }
  }

  const Model& model_;
  const ProbeSpec& spec_;
  long long monitor_every_;
  ProbeResult& r_;
  std::vector<double> times_;  // s, ascending
  size_t next_ = 0;
};

}  // namespace

ProbeResult run_probe(const Simulation& base, const ProbeSpec& spec) {
  if (!(spec.dt > 0.0) || !(spec.duration >= 0.0)) {
    throw InputError("probe: dt must be > 0 and duration >= 0");
  }
  Model model = base.model;
  model.integrator = spec.integrator;
  model.dt = spec.dt;
  State state = base.state;

  ProbeResult r;
  r.steps = spec.steps >= 0 ? spec.steps
                            : static_cast<long long>(std::ceil(spec.duration / spec.dt - 1e-9));
  const long long monitor_every =
      spec.monitor_every > 0 ? spec.monitor_every : std::max<long long>(1, r.steps / 256);

  prepare_start(model, state);  // as the run's Stepper would, before its start is measured
  const Energy e0 = measure_energy(model, state.x, state.v);
  r.energy_start = e0.total();
  r.energy_max = r.energy_start;
  r.energy_scale = energy_scale(model, state);
  r.energy_bound = r.energy_start + spec.energy_margin * r.energy_scale;
  if (!model.obstacles.empty()) r.min_clearance = min_clearance(model, state.x, state.t);

  ProbeObserver observer(model, spec, monitor_every, r);
  DriveSpec drive_spec;
  drive_spec.steps = r.steps;
  drive_spec.end_on_last_good = spec.keep_end;
  drive_spec.interrupted = spec.interrupted;
  drive_spec.same_time = 1e-9;  // the studies' tolerance, tighter than the frames'
  const DriveResult run = drive(model, state, drive_spec, {&observer});
  if (run.end == RunEnd::Diverged) {
    r.status = ProbeStatus::Diverged;
    r.failure = run.divergence;
  } else if (run.end == RunEnd::Interrupted) {
    r.status = ProbeStatus::Interrupted;
  }
  r.steps_done = run.steps_done;
  if (spec.keep_end) r.end = std::move(state);
  r.cpu_seconds = run.totals.cpu_seconds;
  r.wall_seconds = run.totals.wall_seconds;
  r.newton_iterations = run.totals.newton_iterations;
  r.cg_iterations = run.totals.cg_iterations;
  r.simulated_time = static_cast<double>(r.steps_done) * spec.dt;
  return r;
}

}  // namespace tissu
