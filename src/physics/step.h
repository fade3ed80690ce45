// One simulation step as a short pipeline of named stages (design.md):
//   forces -> integrate -> position correction (if declared) -> collisions (if any)
//   -> advance time -> divergence check.
// Explicit steps run the stages per vertex block after the forces' triangle stage, on
// Workspace::threads threads; every vertex is computed the same way on any number of
// threads, so the results are the same bits.
#pragma once

#include <optional>
#include <string>

#include "core/types.h"
#include "physics/model.h"
#include "physics/workspace.h"

namespace tissu {

struct Divergence {
  long long step = 0;  // the step that produced the bad state
  double time = 0.0;   // s
  int vertex = -1;
  std::string reason;  // "non-finite position", "speed 1.2e+03 m/s exceeds 100 m/s", ...
};

// Advances `state` by model.dt. Returns the divergence when the new state is non-finite or
// runs away (a vertex faster than model.max_speed); the state is then left as computed.
std::optional<Divergence> step(const Model& model, State& state, Workspace& ws);

// Collision stage on its own (section 2.3): pushes every free vertex inside an obstacle at
// time t out to its surface and applies the velocity response.
void resolve_collisions(const Model& model, double t, Vec3List& x, Vec3List& v);

}  // namespace tissu
