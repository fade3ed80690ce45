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
#include "physics/obstacle_response.h"
#include "physics/workspace.h"

namespace tissu {

struct Divergence {
  long long step = 0;  // the step that produced the bad state
  double time = 0.0;   // s
  int vertex = -1;
  std::string reason;  // "non-finite position", "speed 1.2e+03 m/s exceeds 100 m/s", ...
};

// A run's start for the implicit integrators, where the barrier acts: layers the scene lays
// within dhat of each other are opened to dhat, and cloth it lays within the gap where an
// obstacle's barrier holds it is moved out to that gap (the barrier model), positions only
// (separate_laid_layers and lift_to_holding_gaps, barrier_contact.h), so that no first step
// throws them apart. Called by the Stepper before a run's first sample and by step() at
// step 0; does nothing past step 0, twice, or for the explicit integrators.
void prepare_start(const Model& model, State& state);

// Advances `state` by model.dt. Returns the divergence when the new state is non-finite,
// runs away (a vertex faster than model.max_speed) or holds far more energy than the scene
// can supply (see energy_limit); the state is then left as computed.
std::optional<Divergence> step(const Model& model, State& state, Workspace& ws);

// The energy a run starting from `start` may reach before it counts as diverged, J: its
// total energy (kinetic + elastic + gravity potential) at the start plus ten times the
// start's kinetic and elastic energy and what the scene can supply, M (|g| L + W^2 / 2 +
// 2 V^2), with M the cloth's mass, L the diagonal of its bounding box at the start, W the
// fastest wind (gusts included) and V the fastest obstacle. Checked after every implicit
// step and every kExplicitEnergyCheck explicit steps.
double energy_limit(const Model& model, const State& start);
constexpr int kExplicitEnergyCheck = 64;

// The obstacle response after an explicit step of the model's integrator: symplectic Euler
// and the paper's scheme move each vertex with its new velocity (x_{n+1} = x_n + h
// v_{n+1}), so friction's change of that velocity changes the position too
// (CollisionResponse::position_weight = dt); explicit Euler moved it with the old one.
CollisionResponse explicit_response(const Model& model);

// Collision stage on its own (section 2.3): moves every free vertex closer to an obstacle
// than its thickness at time t out to that distance and applies the velocity response.
// Every free vertex gets the scalar response, without the step's vectorised near-test:
// the reference that test is checked against (tests/physics/obstacle_simd_test).
void resolve_collisions(const Model& model, double t, Vec3List& x, Vec3List& v);

}  // namespace tissu
