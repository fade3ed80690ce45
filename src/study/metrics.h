// Error and energy measures used by the accuracy study and the stability search.
#pragma once

#include "physics/model.h"

namespace tissu {

// Distance between two configurations of the same mesh, vertex by vertex (m).
// rms = sqrt(mean over all vertices of |a_i - b_i|^2); max = the largest |a_i - b_i| and the
// vertex where it occurs. Pinned vertices count (their distance is 0 in a study).
struct PositionError {
  double rms = 0.0;  // m
  double max = 0.0;  // m
  int max_vertex = -1;
};
PositionError position_error(const Vec3List& a, const Vec3List& b);

// Energies of one state, J. total = kinetic + elastic (membrane + bending) + gravity
// potential (-sum m g.x, zero without gravity).
struct Energy {
  double kinetic = 0.0;
  double elastic = 0.0;
  double potential = 0.0;
  double total() const { return kinetic + elastic + potential; }
};
Energy measure_energy(const Model& model, const Vec3List& x, const Vec3List& v);

// The energy a run may reasonably gain over its duration, J: the work gravity can do over the
// cloth's size, M |g| L (L = diagonal of the cloth's bounding box at the start), plus the
// kinetic energy external drivers can give the whole cloth, M v_ext^2 / 2 (v_ext = the
// largest wind speed, or twice the largest obstacle speed: a rigid wall bounces a vertex at
// most at twice its own speed), plus the starting kinetic and elastic energies.
// A run whose total energy exceeds start + margin * scale is flagged as energy growing
// without bound. Never below 1e-9 J.
double energy_scale(const Model& model, const State& start);

// Largest speed an obstacle reaches, m/s (|drift| + |amplitude| 2 pi / period).
double max_obstacle_speed(const Obstacle& obstacle);

// Sum of the lumped masses, kg.
double total_mass(const Model& model);

}  // namespace tissu
