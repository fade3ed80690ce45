#include "physics/step.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include <Eigen/Geometry>

#include "physics/barrier_contact.h"
#include "physics/diagnostics.h"
#include "physics/force_plan.h"
#include "physics/forces.h"
#include "physics/implicit.h"
#include "physics/membrane.h"
#include "physics/obstacle_response.h"
#include "physics/parallel.h"
#include "physics/step_scratch.h"
#include "physics/vertex_pass.h"
#include "physics/vertex_pass_simd.h"

namespace tissu {

namespace {

// Section 3, as printed: halve the displacement of a vertex up to n_it times while it is
// longer than the threshold; if the last measured displacement exceeded the threshold,
// recompute the velocity from the corrected displacement.
void correct_position(const PositionCorrection& pc, double h, const Vec3& x_old, Vec3& x,
                      Vec3& v) {
  double dist = 0.0;
  for (int it = 0; it < pc.iterations; ++it) {
    const Vec3 diff = x - x_old;
    dist = diff.norm();
    if (dist > pc.threshold) x = x_old + diff / 2.0;
  }
  if (dist > pc.threshold) v = (x - x_old) / h;
}

void place_obstacles(const Model& model, double t, std::vector<PlacedObstacle>& placed) {
  placed.clear();
  for (const Obstacle& ob : model.obstacles) placed.push_back(place_obstacle(ob, t));
}

// The blocks' findings in vertex order: the first non-finite vertex, else the first of
// the fastest when it exceeds model.max_speed.
std::optional<Divergence> divergence_of(const Model& model, const State& state,
                                        const std::vector<BlockCheck>& checks) {
  int fastest = -1;
  double top_speed2 = 0.0;
  for (const BlockCheck& c : checks) {
    if (c.first_bad >= 0) {
      return Divergence{state.step, state.t, c.first_bad,
                        c.bad_position ? "non-finite position" : "non-finite velocity"};
    }
    if (c.top_speed2 > top_speed2) {
      top_speed2 = c.top_speed2;
      fastest = c.fastest;
    }
  }
  if (top_speed2 > model.max_speed * model.max_speed) {
    std::ostringstream reason;
    reason.precision(3);
    reason << "speed " << std::sqrt(top_speed2) << " m/s exceeds the limit of "
           << model.max_speed << " m/s";
    return Divergence{state.step, state.t, fastest, reason.str()};
  }
  return std::nullopt;
}

// The free vertex holding the most kinetic and membrane energy (a third of each of its
// triangles'), where a run that gains energy has gone wrong.
int vertex_holding_most_energy(const Model& model, const State& state) {
  std::vector<double> held(model.num_vertices(), 0.0);  // J
  std::vector<double> triangles;
  triangle_energies(model, state.x, triangles);
  for (size_t t = 0; t < model.triangles.size(); ++t) {
    for (const int i : model.triangles[t]) held[i] += triangles[t] / 3.0;
  }
  int most = -1;
  for (int i = 0; i < model.num_vertices(); ++i) {
    if (model.pinned[i]) continue;
    held[i] += 0.5 * model.mass[i] * state.v[i].squaredNorm();
    if (most < 0 || held[i] > held[most]) most = i;
  }
  return most;
}

// Energy beyond the workspace's limit: a divergence naming the energy and the limit.
std::optional<Divergence> energy_divergence(const Model& model, const State& state,
                                            double limit) {
  const double energy = total_energy(model, state);
  if (energy <= limit) return std::nullopt;
  std::ostringstream reason;
  reason.precision(3);
  reason << "energy " << energy << " J exceeds the " << limit
         << " J this scene can reach (its start plus ten times what gravity, wind and moving "
            "obstacles supply)";
  return Divergence{state.step, state.t, vertex_holding_most_energy(model, state), reason.str()};
}

}  // namespace

CollisionResponse explicit_response(const Model& model) {
  CollisionResponse response = kExplicitResponse;
  if (model.integrator != Integrator::ExplicitEuler) response.position_weight = model.dt;
  return response;
}

double energy_limit(const Model& model, const State& start) {
  return total_energy(model, start) + 10.0 * energy_scale(model, start);
}

void resolve_collisions(const Model& model, double t, Vec3List& x, Vec3List& v) {
  std::vector<PlacedObstacle> placed;
  place_obstacles(model, t, placed);
  const CollisionResponse response = explicit_response(model);
  for (int i = 0; i < model.num_vertices(); ++i) {
    if (!model.pinned[i]) collide_vertex(placed, response, x[i], v[i]);
  }
}

void prepare_start(const Model& model, State& state) {
  if (state.step != 0 || state.start_placed || is_explicit(model.integrator)) return;
  state.start_placed = true;
  if (model.self_collision) separate_laid_layers(model, state.x, state.t);
  if (model.implicit.contact != ContactModel::Barrier || model.obstacles.empty()) return;
  Vec3List f;
  compute_forces(model, state.x, state.v, state.t, f);
  const int lifted = lift_to_holding_gaps(model, state.x, f, state.t);
  // Layers the lift brought together again are opened again.
  if (model.self_collision && lifted > 0) separate_laid_layers(model, state.x, state.t);
}

std::optional<Divergence> step(const Model& model, State& state, Workspace& ws) {
  const int n = model.num_vertices();
  const double h = model.dt;
  const double t_new = static_cast<double>(state.step + 1) * h;
  StepScratch& scratch = scratch_of(ws);
  ForcePlan& forces = scratch.forces;
  forces.plan(model);
  scratch.f.resize(n);
  scratch.checks.assign(forces.num_blocks(), BlockCheck{});
  place_obstacles(model, t_new, scratch.placed);
  const bool explicit_step = is_explicit(model.integrator);
  const int threads = force_threads(ws.threads, model);
  const bool contact_stage = needs_cloth_contact(model);
  if (contact_stage && explicit_step) scratch.x_start = state.x;
  prepare_start(model, state);
  if (!scratch.has_energy_limit) {
    scratch.energy_limit = energy_limit(model, state);
    scratch.has_energy_limit = true;
    scratch.obstacle_work = 0.0;
  }
  // A moving obstacle can push cloth held by its pins as far as it goes: the energy the
  // check allows grows by the work it measures it doing.
  const bool moving = has_moving_obstacle(model, state.t, t_new);
  if (moving && explicit_step) scratch.block_work.assign(forces.num_blocks(), 0.0);
  if (moving && !explicit_step) {
    scratch.step_start.x = state.x;
    scratch.step_start.v = state.v;
    scratch.step_start.t = state.t;
  }

  if (model.position_correction) scratch.x_old.resize(n);
  if (explicit_step) {
    forces_stage1(model, state.x, state.v, state.t, threads, forces, scratch.f);
  } else {
    if (model.position_correction) scratch.x_old = state.x;
    integrate_implicit(model, state, ws);
  }

  // Per vertex block: finish the forces and integrate (explicit), correct, collide, check.
  // Without position correction an explicit step finishes the forces, integrates and (with
  // no obstacle to move vertices afterwards) checks in one vectorised pass.
  const bool fused = explicit_step && !model.position_correction;
  const bool fused_check = fused && scratch.placed.empty();
  const CollisionResponse response = explicit_step ? explicit_response(model) : kImplicitResponse;
  parallel_for(threads, forces.num_blocks(), [&](int block) {
    const int first = forces.block_begin(block), end = forces.block_end(block);
    if (fused) {
      finish_block_simd(model, forces, block, scratch.f, state.x, state.v,
                        fused_check ? &scratch.checks[block] : nullptr);
    } else if (explicit_step) {
      forces_stage2(model, state.v, block, forces, scratch.f);
      if (model.position_correction) {
        std::copy(state.x.begin() + first, state.x.begin() + end, scratch.x_old.begin() + first);
      }
      integrate_vertices(model, first, end, scratch.f, state.x, state.v);
    }
    if (model.position_correction) {
      for (int i = first; i < end; ++i) {
        correct_position(*model.position_correction, h, scratch.x_old[i], state.x[i],
                         state.v[i]);
      }
    }
    if (!scratch.placed.empty()) {
      const double work = collide_block(scratch.placed, response, model.pinned, model.mass,
                                        first, end, state.x, state.v);
      if (moving && explicit_step) scratch.block_work[block] = work;
    }
    if (fused_check) return;
    if (fused) {
      check_block_simd(state.x, state.v, first, end, scratch.checks[block]);
      return;
    }
    for (int i = first; i < end; ++i) {
      check_vertex(i, state.x[i], state.v[i], scratch.checks[block]);
    }
  });

  // Cloth against itself and against mesh obstacles' features, around the integrator (the
  // implicit integrators run it inside their steps, see integrate_implicit).
  if (contact_stage && explicit_step) {
    ws.contact = ContactStats{};
    ws.contact_seconds = 0.0;
    if (!scratch.placed.empty()) scratch.x_staged = state.x;
    run_collision_stage(model, state.t, h, scratch.x_start, state, ws);
    // The stage's impulses between cloth and a mesh obstacle's edges, or between layers,
    // can push a vertex into an obstacle; obstacles are never crossed, so a vertex the
    // stage moved gets the obstacles' response again (the explicit one: this is an
    // explicit step).
    for (int i = 0; i < n && !scratch.placed.empty(); ++i) {
      if (model.pinned[i] || state.x[i] == scratch.x_staged[i]) continue;
      const double work = collide_vertex(scratch.placed, response, state.x[i], state.v[i]);
      if (moving) scratch.block_work[0] += model.mass[i] * work;  // summed with the blocks'
    }
  }

  if (moving) {
    double work = 0.0;  // J
    if (explicit_step) {
      for (double w : scratch.block_work) work += w;
    } else {
      work = moving_obstacles_work(model, scratch.step_start, state, h, ws);
    }
    scratch.obstacle_work += std::max(work, 0.0);
  }

  state.step += 1;
  state.t = t_new;
  std::optional<Divergence> divergence = divergence_of(model, state, scratch.checks);
  if (!divergence && (!explicit_step || state.step % kExplicitEnergyCheck == 0)) {
    divergence =
        energy_divergence(model, state, scratch.energy_limit + 10.0 * scratch.obstacle_work);
  }
  return divergence;
}

}  // namespace tissu
