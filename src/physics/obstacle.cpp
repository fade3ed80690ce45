#include "physics/obstacle.h"

#include <algorithm>
#include <cmath>

namespace tissu {

Vec3 Obstacle::offset(double t) const {
  Vec3 o = motion.velocity * t;
  if (motion.period > 0.0) o += motion.amplitude * std::sin(2.0 * M_PI * t / motion.period);
  return o;
}

Vec3 Obstacle::velocity(double t) const {
  Vec3 v = motion.velocity;
  if (motion.period > 0.0) {
    const double w = 2.0 * M_PI / motion.period;
    v += motion.amplitude * (w * std::cos(w * t));
  }
  return v;
}

namespace {

// Any unit vector perpendicular to `axis`.
Vec3 perpendicular(const Vec3& axis) {
  const Vec3 helper = std::fabs(axis.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  return axis.cross(helper).normalized();
}

double sphere_distance(const Vec3& p, const Vec3& c, double radius, Vec3* normal) {
  const Vec3 d = p - c;
  const double r = d.norm();
  *normal = r > 0.0 ? Vec3(d / r) : Vec3::UnitZ();
  return r - radius;
}

// Finite cylinder with flat caps: exact signed distance and the normal of the closest
// surface point (side or cap; the rim, outside, by the distance to the rim circle).
double cylinder_distance(const Vec3& p, const Vec3& c, const Vec3& axis, double radius,
                         double half_length, Vec3* normal) {
  const Vec3 d = p - c;
  const double h = d.dot(axis);
  const Vec3 radial = d - h * axis;
  const double r = radial.norm();
  const Vec3 radial_dir = r > 1e-300 ? Vec3(radial / r) : perpendicular(axis);
  const double side = r - radius;                    // > 0 outside the infinite cylinder
  const double cap = std::fabs(h) - half_length;     // > 0 beyond the caps
  const Vec3 cap_normal = h >= 0.0 ? axis : Vec3(-axis);
  if (side <= 0.0 && cap <= 0.0) {  // inside: nearest of side and caps
    if (side >= cap) {
      *normal = radial_dir;
      return side;
    }
    *normal = cap_normal;
    return cap;
  }
  if (cap <= 0.0) {
    *normal = radial_dir;
    return side;
  }
  if (side <= 0.0) {
    *normal = cap_normal;
    return cap;
  }
  const Vec3 to_rim = side * radial_dir + cap * cap_normal;
  const double dist = to_rim.norm();
  *normal = to_rim / dist;
  return dist;
}

}  // namespace

double Obstacle::signed_distance(const Vec3& p, double t, Vec3* normal) const {
  return signed_distance_from(p, center_at(t), normal);
}

double Obstacle::signed_distance_from(const Vec3& p, const Vec3& c, Vec3* normal) const {
  switch (kind) {
    case ObstacleKind::Sphere: return sphere_distance(p, c, radius, normal);
    case ObstacleKind::Cylinder: return cylinder_distance(p, c, axis, radius, half_length, normal);
    case ObstacleKind::Plane:
      *normal = axis;
      return (p - c).dot(axis);
  }
  return 0.0;
}

const char* obstacle_kind_name(ObstacleKind kind) {
  switch (kind) {
    case ObstacleKind::Sphere: return "sphere";
    case ObstacleKind::Cylinder: return "cylinder";
    case ObstacleKind::Plane: return "plane";
  }
  return "unknown";
}

}  // namespace tissu
