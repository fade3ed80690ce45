// Quantities reported per frame: energies, speeds, strain, obstacle clearance.
#pragma once

#include <optional>

#include "physics/model.h"

namespace tissu {

struct FrameStats {
  long long step = 0;
  double time = 0.0;             // s
  double kinetic_energy = 0.0;   // J
  double elastic_energy = 0.0;   // J (membrane + bending)
  double potential_energy = 0.0; // J, gravity (-sum m g.x), 0 without gravity
  double max_speed = 0.0;        // m/s
  double max_strain = 0.0;       // largest principal Green strain
  std::optional<double> min_clearance;  // m, smallest signed obstacle distance; none without obstacles
};

double kinetic_energy(const Model& model, const Vec3List& v);
double elastic_energy(const Model& model, const Vec3List& x);
double gravity_potential(const Model& model, const Vec3List& x);
std::optional<double> min_clearance(const Model& model, const Vec3List& x, double t);

// Kinetic + elastic + gravity potential, J.
double total_energy(const Model& model, const State& state);

// Sum of the lumped masses, kg.
double total_mass(const Model& model);

// Largest speed an obstacle's surface reaches, m/s: |drift| + |amplitude| 2 pi / period,
// plus its fastest keyframe segment (translation, and a mesh's turn times its reach).
double max_obstacle_speed(const Obstacle& obstacle);

// Whether an obstacle moves within [t0, t1] (s): it can then put energy into the cloth
// through its contacts over that time.
bool has_moving_obstacle(const Model& model, double t0, double t1);

// The energy a run may reasonably gain over its duration, J: the work gravity can do over the
// cloth's size, M |g| L (L = diagonal of the cloth's bounding box at the start), plus the
// kinetic energy external drivers can give the whole cloth, M v_ext^2 / 2 (v_ext = the
// largest wind speed, or twice the largest obstacle speed: a rigid wall bounces a vertex at
// most at twice its own speed), plus the starting kinetic and elastic energies. The
// divergence check of a run (step.h) and the studies' energy bound are multiples of it.
// Never below 1e-9 J.
double energy_scale(const Model& model, const State& start);
FrameStats measure_frame(const Model& model, const State& state);

}  // namespace tissu
