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
FrameStats measure_frame(const Model& model, const State& state);

}  // namespace tissu
