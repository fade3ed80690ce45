#include "physics/diagnostics.h"

#include <algorithm>
#include <cmath>

#include "physics/bending.h"
#include "physics/membrane.h"

namespace tissu {

double kinetic_energy(const Model& model, const Vec3List& v) {
  double e = 0.0;
  for (int i = 0; i < model.num_vertices(); ++i) e += 0.5 * model.mass[i] * v[i].squaredNorm();
  return e;
}

double elastic_energy(const Model& model, const Vec3List& x) {
  return membrane_energy(model, x) + (model.bending ? bending_energy(*model.bending, x) : 0.0);
}

double gravity_potential(const Model& model, const Vec3List& x) {
  if (!model.gravity) return 0.0;
  double e = 0.0;
  for (int i = 0; i < model.num_vertices(); ++i) e -= model.mass[i] * model.gravity->dot(x[i]);
  return e;
}

std::optional<double> min_clearance(const Model& model, const Vec3List& x, double t) {
  if (model.obstacles.empty()) return std::nullopt;
  double best = INFINITY;
  for (const Obstacle& ob : model.obstacles) {
    for (const Vec3& p : x) {
      Vec3 n;
      best = std::min(best, ob.signed_distance(p, t, &n));
    }
  }
  return best;
}

FrameStats measure_frame(const Model& model, const State& state) {
  FrameStats s;
  s.step = state.step;
  s.time = state.t;
  s.kinetic_energy = kinetic_energy(model, state.v);
  s.elastic_energy = elastic_energy(model, state.x);
  s.potential_energy = gravity_potential(model, state.x);
  for (const Vec3& v : state.v) s.max_speed = std::max(s.max_speed, v.norm());
  s.max_strain = max_principal_strain(model, state.x);
  s.min_clearance = min_clearance(model, state.x, state.t);
  return s;
}

}  // namespace tissu
