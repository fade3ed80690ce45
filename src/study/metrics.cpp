#include "study/metrics.h"

#include <algorithm>
#include <cmath>

#include "physics/diagnostics.h"

namespace tissu {

PositionError position_error(const Vec3List& a, const Vec3List& b) {
  PositionError e;
  const size_t n = std::min(a.size(), b.size());
  if (n == 0) return e;
  double sum2 = 0.0;
  for (size_t i = 0; i < n; ++i) {
    const double d2 = (a[i] - b[i]).squaredNorm();
    sum2 += d2;
    if (d2 > e.max * e.max || e.max_vertex < 0) {
      e.max = std::sqrt(d2);
      e.max_vertex = static_cast<int>(i);
    }
  }
  e.rms = std::sqrt(sum2 / static_cast<double>(n));
  return e;
}

Energy measure_energy(const Model& model, const Vec3List& x, const Vec3List& v) {
  Energy e;
  e.kinetic = kinetic_energy(model, v);
  e.elastic = elastic_energy(model, x);
  e.potential = gravity_potential(model, x);
  return e;
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
  return speed;
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
  if (model.wind) v_ext = model.wind->velocity.norm() * (1.0 + model.wind->gust_amplitude);
  for (const Obstacle& ob : model.obstacles) v_ext = std::max(v_ext, 2.0 * max_obstacle_speed(ob));
  scale += 0.5 * mass * v_ext * v_ext;
  // What the start already holds.
  const Energy e0 = measure_energy(model, start.x, start.v);
  scale += e0.kinetic + e0.elastic;
  return std::max(scale, 1e-9);
}

}  // namespace tissu
