#include "physics/stepper.h"

#include <utility>

#include "core/cpu_clock.h"

namespace tissu {

Stepper::Stepper(const Model& model, State& state, int threads) : model_(model), state_(state) {
  ws_.threads = threads;
  prepare_start(model, state);  // before the run's first sample
}

std::optional<Divergence> Stepper::advance(bool keep_before) {
  before_.x.clear();
  before_.v.clear();
  if (keep_before) {
    before_.x = state_.x;
    before_.v = state_.v;
    before_.t = state_.t;
    before_.step = state_.step;
  }
  const double wall0 = wall_seconds();
  const double cpu0 = thread_cpu_seconds();
  std::optional<Divergence> divergence = step(model_, state_, ws_);
  totals_.cpu_seconds += thread_cpu_seconds() - cpu0;
  totals_.wall_seconds += wall_seconds() - wall0;
  totals_.steps += 1;
  totals_.newton_iterations += ws_.newton_iterations;
  totals_.cg_iterations += ws_.cg_iterations;
  totals_.contact_seconds += ws_.contact_seconds;
  totals_.contact_proximities += ws_.contact.proximities;
  totals_.contact_impacts += ws_.contact.impacts;
  totals_.contact_rebuilds += ws_.contact.rebuilt ? 1 : 0;
  totals_.contact_zones += ws_.contact.zones;
  totals_.contact_rigid_zones += ws_.contact.rigid_zones;
  totals_.contact_unresolved += ws_.contact.unresolved;
  totals_.barrier_pairs += ws_.barrier_pairs;
  return divergence;
}

void Stepper::restore_before() {
  std::swap(state_.x, before_.x);
  std::swap(state_.v, before_.v);
  state_.t = before_.t;
  state_.step = before_.step;
  before_.x.clear();
  before_.v.clear();
}

}  // namespace tissu
