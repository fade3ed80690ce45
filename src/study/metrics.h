// Error and energy measures used by the accuracy study and the stability search.
#pragma once

#include "physics/diagnostics.h"  // energy_scale, total_mass, max_obstacle_speed
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

// Largest vertex speed of the velocities `v`, m/s (0 for none).
double max_speed(const Vec3List& v);

// Mass-weighted mean of the positions `x` (m), with the model's lumped masses.
Vec3 centre_of_mass(const Model& model, const Vec3List& x);

// Energies of one state, J. total = kinetic + elastic (membrane + bending) + gravity
// potential (-sum m g.x, zero without gravity).
struct Energy {
  double kinetic = 0.0;
  double elastic = 0.0;
  double potential = 0.0;
  double total() const { return kinetic + elastic + potential; }
};
Energy measure_energy(const Model& model, const Vec3List& x, const Vec3List& v);

}  // namespace tissu
