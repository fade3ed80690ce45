// One simulation step as a short pipeline of named stages (design.md):
//   forces -> integrate -> position correction (if declared) -> collisions (if any)
//   -> advance time -> divergence check.
#pragma once

#include <memory>
#include <optional>
#include <string>

#include "core/types.h"
#include "physics/model.h"

namespace tissu {

struct ImplicitSolver;  // physics/implicit.cpp: Newton/PCG caches of the implicit steps

// Scratch memory reused across steps (no allocation in the step after the first).
struct Workspace {
  Vec3List f;      // (V) forces, N
  Vec3List x_old;  // (V) positions at the start of the step, m (position correction)
  Vec3List x_prev, v_prev;  // (V) previous step's state (BDF-2)
  bool has_prev = false;
  // Implicit solver statistics of the last step.
  int newton_iterations = 0;
  int cg_iterations = 0;
  // Jacobian pattern and solver scratch of the implicit integrators, created by the first
  // implicit step (copies of a Workspace share it: do not step copies concurrently).
  std::shared_ptr<ImplicitSolver> implicit;
};

struct Divergence {
  long long step = 0;  // the step that produced the bad state
  double time = 0.0;   // s
  int vertex = -1;
  std::string reason;  // "non-finite position", "speed 1.2e+03 m/s exceeds 100 m/s", ...
};

// Advances `state` by model.dt. Returns the divergence when the new state is non-finite or
// runs away (a vertex faster than model.max_speed); the state is then left as computed.
std::optional<Divergence> step(const Model& model, State& state, Workspace& ws);

// Stages, exposed for tests and for other integrators.
void integrate_explicit(const Model& model, State& state, Workspace& ws);
void apply_position_correction(const Model& model, const Vec3List& x_old, State& state);
void resolve_collisions(const Model& model, double t, Vec3List& x, Vec3List& v);
std::optional<Divergence> check_divergence(const Model& model, const State& state);

}  // namespace tissu
