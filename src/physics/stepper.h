// Taking a run's steps: each step keeps, on request, the state it started from (for frames
// or samples that fall inside it, and to fall back on after a divergence), and adds what it
// cost and did to the run's totals. The run driver (run_driver.h), which every loop around
// step() is made of, takes its steps with it.
#pragma once

#include <optional>

#include "physics/step.h"

namespace tissu {

struct StepTotals {
  long long steps = 0;
  long long newton_iterations = 0;  // implicit integrators
  long long cg_iterations = 0;
  double wall_seconds = 0.0;  // s, monotonic clock
  double cpu_seconds = 0.0;   // s, processor time of the calling thread
  // The collision stage (physics/cloth_contact.h), when the scene has one.
  double contact_seconds = 0.0;  // s, processor time
  long long contact_proximities = 0, contact_impacts = 0, contact_rebuilds = 0,
            contact_zones = 0, contact_rigid_zones = 0, contact_unresolved = 0;
  // Self and mesh feature pairs the implicit solve's barrier held at the end of each step.
  long long barrier_pairs = 0;
};

class Stepper {
 public:
  // Steps `state` of `model` (both outlive the stepper) on `threads` threads. A state at its
  // run's start is prepared for it first (prepare_start, step.h).
  Stepper(const Model& model, State& state, int threads = 1);

  // One step. With keep_before, before() holds the state it started from (positions,
  // velocities, time and step count); otherwise before() is emptied.
  std::optional<Divergence> advance(bool keep_before);

  const State& before() const { return before_; }
  bool has_before() const { return !before_.x.empty(); }
  // Puts the state back to before() (after a divergence, to end on the last good state).
  void restore_before();

  const StepTotals& totals() const { return totals_; }
  const Workspace& workspace() const { return ws_; }

 private:
  const Model& model_;
  State& state_;
  Workspace ws_;
  State before_;
  StepTotals totals_;
};

}  // namespace tissu
