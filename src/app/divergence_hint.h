// After a run diverged: a time step that gets the same scene past the point where it
// diverged, found by halving the scene's step (a short search, within a fixed budget of
// steps), and the command that checks a step over the whole run.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "physics/step.h"
#include "scene/scene.h"

namespace tissu {

struct DivergenceHint {
  std::optional<double> working_dt;  // s: ran stably to `checked_until`
  double checked_until = 0.0;        // s of simulated time each try ran (or tried to)
  double smallest_failed_dt = 0.0;   // s: the smallest step tried that was not stable
  int tries = 0;                     // steps tried below the scene's
  std::string stability_command;     // tissu stability ... for the whole run
};

// Tries dt/2, dt/4, ... on a fresh copy of `initial` (the scene's simulation at t = 0) up
// to min(duration, 2 * the divergence time), stopping at the first stable one (probe.h:
// no divergence, energy bound, no obstacle penetration) or when the next try would take
// the search past `budget` triangle-steps (steps times triangles; 1e8 is about 2 s of
// explicit steps at docs/performance.md's 21 ns per triangle-step). Deterministic: the
// budget counts work, not time.
DivergenceHint find_divergence_hint(const Scene& scene, const Simulation& initial,
                                    const Divergence& divergence,
                                    const std::vector<std::string>& overrides,
                                    double budget = 1e8);

// "a step of 2.5e-4 s runs to t = 0.062 s without diverging; for the whole run: tissu
// stability ..." (or, without a working step, the command only).
std::string divergence_hint_text(const DivergenceHint& hint);

}  // namespace tissu
