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

double max_speed(const Vec3List& v) {
  double top = 0.0;
  for (const Vec3& vi : v) top = std::max(top, vi.norm());
  return top;
}

Vec3 centre_of_mass(const Model& model, const Vec3List& x) {
  Vec3 sum = Vec3::Zero();
  double mass = 0.0;
  for (int i = 0; i < model.num_vertices(); ++i) {
    sum += model.mass[i] * x[i];
    mass += model.mass[i];
  }
  return sum / mass;
}

Energy measure_energy(const Model& model, const Vec3List& x, const Vec3List& v) {
  Energy e;
  e.kinetic = kinetic_energy(model, v);
  e.elastic = elastic_energy(model, x);
  e.potential = gravity_potential(model, x);
  return e;
}

}  // namespace tissu
