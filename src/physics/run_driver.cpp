#include "physics/run_driver.h"

#include <cmath>

namespace tissu {

namespace {

bool all_want_more(const std::vector<RunObserver*>& observers) {
  for (const RunObserver* o : observers) {
    if (!o->wants_more()) return false;
  }
  return true;
}

// True when a sample time of some observer falls before the end of the next step, so the
// state before it must be kept to interpolate.
bool sample_inside_next_step(const std::vector<RunObserver*>& observers, const State& state,
                             double dt, double same_time) {
  for (const RunObserver* o : observers) {
    const std::optional<double> t = o->next_sample_time();
    if (t && *t < state.t + (1.0 - same_time) * dt) return true;
  }
  return false;
}

// Linear interpolation of positions and velocities at time t between `before` and `after`,
// the states at the two ends of one step.
void interpolate(const State& before, const State& after, double t, State& between) {
  const double w = (t - before.t) / (after.t - before.t);
  between.t = t;
  between.step = before.step;
  between.x.resize(after.x.size());
  between.v.resize(after.v.size());
  for (size_t i = 0; i < after.x.size(); ++i) {
    between.x[i] = (1.0 - w) * before.x[i] + w * after.x[i];
    between.v[i] = (1.0 - w) * before.v[i] + w * after.v[i];
  }
}

// Hands `o` the samples due at `state`, the state after `steps` steps of the run: by time,
// those up to this step's time (`before` is the state before the step, or null when it was
// not kept or there is no step yet), then by step. `tol` is the same-time tolerance, s.
void deliver_samples(RunObserver& o, const State& state, const State* before, long long steps,
                     double tol, State& between) {
  for (std::optional<double> t = o.next_sample_time(); t; t = o.next_sample_time()) {
    if (std::fabs(*t - state.t) <= tol || (steps == 0 && *t <= state.t + tol)) {
      o.sample(state, {*t, steps, false});
    } else if (before && *t < state.t - tol) {
      interpolate(*before, state, *t, between);
      o.sample(between, {*t, steps - 1, true});
    } else {
      break;
    }
  }
  const long long every = o.sample_every();
  if (every > 0 && steps % every == 0) o.sample(state, {state.t, steps, false});
}

}  // namespace

DriveResult drive(const Model& model, State& state, const DriveSpec& spec,
                  const std::vector<RunObserver*>& observers) {
  Stepper stepper(model, state, spec.threads);
  DriveResult result;
  const double tol = spec.same_time * model.dt;  // s
  State between;
  for (long long s = 0;; ++s) {
    for (RunObserver* o : observers) o->reached(state, s);
    if (s > 0 && !all_want_more(observers)) {
      result.end = RunEnd::Stopped;
      break;
    }
    const State* before = s > 0 && stepper.has_before() ? &stepper.before() : nullptr;
    for (RunObserver* o : observers) deliver_samples(*o, state, before, s, tol, between);
    if (s >= spec.steps) break;
    if (!all_want_more(observers)) {
      result.end = RunEnd::Stopped;
      break;
    }
    if (spec.interrupted && spec.interrupted()) {
      result.end = RunEnd::Interrupted;
      break;
    }
    const bool keep_before = spec.end_on_last_good ||
                             sample_inside_next_step(observers, state, model.dt, spec.same_time);
    const std::optional<Divergence> divergence = stepper.advance(keep_before);
    result.steps_done = s + 1;
    if (divergence) {
      result.end = RunEnd::Diverged;
      result.divergence = divergence;
      if (spec.end_on_last_good) stepper.restore_before();
      break;
    }
  }
  result.totals = stepper.totals();
  for (RunObserver* o : observers) o->finish(state, result);
  return result;
}

}  // namespace tissu
