// One simulation step as a short pipeline of named stages (design.md):
//   forces -> integrate -> position correction (if declared) -> collisions (if any)
//   -> advance time -> divergence check.
// Explicit steps run the stages per vertex block after the forces' triangle stage, on
// Workspace::threads threads; every vertex is computed the same way on any number of
// threads, so the results are the same bits.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/types.h"
#include "physics/forces.h"
#include "physics/model.h"

namespace tissu {

struct ImplicitSolver;  // physics/implicit.cpp: Newton/PCG caches of the implicit steps

// An obstacle placed at one time: its centre (or plane point) and rigid velocity.
struct PlacedObstacle {
  const Obstacle* obstacle = nullptr;
  Vec3 center = Vec3::Zero();    // m
  Vec3 velocity = Vec3::Zero();  // m/s
};

// What the divergence check found in one vertex block.
struct BlockCheck {
  int first_bad = -1;           // first vertex with a non-finite position or velocity
  bool bad_position = false;    // that vertex's position (not only its velocity) is bad
  int fastest = -1;             // first vertex with the largest speed
  double top_speed2 = 0.0;      // its squared speed, m^2/s^2
};

// Scratch memory reused across steps (no allocation in the step after the first). A
// Workspace serves one Model: its caches are planned from the model it first steps.
struct Workspace {
  // Threads a step may use (the calling thread included). Results do not depend on it.
  int threads = 1;
  Vec3List f;      // (V) forces, N
  Vec3List x_old;  // (V) positions at the start of the step, m (position correction)
  Vec3List x_prev, v_prev;  // (V) previous step's state (BDF-2)
  bool has_prev = false;
  ChunkedForces forces;                 // force summation order and buffers
  std::vector<PlacedObstacle> placed;   // obstacles at the end of the step
  std::vector<BlockCheck> checks;       // (vertex blocks) divergence check
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

// Collision stage on its own (section 2.3): pushes every free vertex inside an obstacle at
// time t out to its surface and applies the velocity response.
void resolve_collisions(const Model& model, double t, Vec3List& x, Vec3List& v);

}  // namespace tissu
