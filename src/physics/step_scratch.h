// Scratch memory of the step behind Workspace::scratch (internal to the physics library).
#pragma once

#include <memory>
#include <vector>

#include "core/types.h"
#include "physics/force_plan.h"
#include "physics/obstacle.h"
#include "physics/workspace.h"

namespace tissu {

struct ImplicitSolver;  // physics/implicit.cpp: Newton/PCG caches of the implicit steps

// What the divergence check found in one vertex block.
struct BlockCheck {
  int first_bad = -1;           // first vertex with a non-finite position or velocity
  bool bad_position = false;    // that vertex's position (not only its velocity) is bad
  int fastest = -1;             // first vertex with the largest speed
  double top_speed2 = 0.0;      // its squared speed, m^2/s^2
};

struct StepScratch {
  ForcePlan forces;                     // force summation order and buffers
  Vec3List f;                           // (V) forces, N
  Vec3List x_old;                       // (V) positions at the start of the step, m
  std::vector<PlacedObstacle> placed;   // obstacles at the end of the step
  std::vector<BlockCheck> checks;       // (vertex blocks) divergence check
  std::shared_ptr<ImplicitSolver> implicit;  // created by the first implicit step
  std::shared_ptr<ClothContact> contact;     // collision stage, when the model needs it
  Vec3List x_start;                          // (V) positions at the step's start, m
  Vec3List x_staged;                         // (V) positions before the collision stage, m
  double energy_limit = 0.0;  // J, of the state the workspace first stepped (energy_limit)
  bool has_energy_limit = false;
  // Moving obstacles' work on the cloth since then, J: the positive part of each step's,
  // which the limit takes ten times.
  double obstacle_work = 0.0;
  std::vector<double> block_work;  // (vertex blocks) this step's, explicit steps, J
  State step_start;                // positions and velocities at an implicit step's start
};

// The workspace's scratch, created on first use.
inline StepScratch& scratch_of(Workspace& ws) {
  if (!ws.scratch) ws.scratch = std::make_shared<StepScratch>();
  return *ws.scratch;
}

}  // namespace tissu
