#include "physics/diagnostics.h"

#include <algorithm>
#include <cmath>

#include "collision/closed_surface.h"
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

double total_energy(const Model& model, const State& state) {
  return kinetic_energy(model, state.v) + elastic_energy(model, state.x) +
         gravity_potential(model, state.x);
}

double total_mass(const Model& model) {
  double m = 0.0;
  for (double mi : model.mass) m += mi;
  return m;
}

double max_obstacle_speed(const Obstacle& obstacle) {
  const ObstacleMotion& m = obstacle.motion;
  double speed = m.velocity.norm();
  if (m.period > 0.0) speed += m.amplitude.norm() * 2.0 * M_PI / m.period;
  if (m.keyframes.size() < 2) return speed;
  // Keyframes: the fastest segment, whose turn carries the surface point farthest from the
  // centre (meshes turn; the other obstacles only move).
  double reach = 0.0;  // m
  if (obstacle.surface) {
    for (const Vec3& p : obstacle.surface->vertices()) {
      reach = std::max(reach, (p - obstacle.center).norm());
    }
  }
  double fastest = 0.0;  // m/s
  for (size_t k = 1; k < m.keyframes.size(); ++k) {
    const Keyframe& a = m.keyframes[k - 1];
    const Keyframe& b = m.keyframes[k];
    const double span = b.time - a.time;  // s, > 0 (validated with the scene)
    const double turn = obstacle.surface ? a.rotation.angularDistance(b.rotation) : 0.0;
    fastest = std::max(fastest, ((b.translation - a.translation).norm() + turn * reach) / span);
  }
  return speed + fastest;
}

bool has_moving_obstacle(const Model& model, double t0, double t1) {
  for (const Obstacle& ob : model.obstacles) {
    if (ob.motion.moves_between(t0, t1)) return true;
  }
  return false;
}

double energy_scale(const Model& model, const State& start) {
  const double mass = total_mass(model);
  double scale = 0.0;
  // Work gravity can do as the cloth moves by about its own size.
  if (model.gravity && !start.x.empty()) {
    Vec3 lo = start.x[0], hi = start.x[0];
    for (const Vec3& p : start.x) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
    scale += mass * model.gravity->norm() * (hi - lo).norm();
  }
  // Kinetic energy external drivers can give.
  double v_ext = 0.0;
  if (model.wind) v_ext = model.wind->velocity.norm() * (1.0 + std::fabs(model.wind->gust_amplitude));
  for (const Obstacle& ob : model.obstacles) v_ext = std::max(v_ext, 2.0 * max_obstacle_speed(ob));
  scale += 0.5 * mass * v_ext * v_ext;
  // What the start already holds.
  scale += kinetic_energy(model, start.v) + elastic_energy(model, start.x);
  return std::max(scale, 1e-9);
}

}  // namespace tissu
