#include "physics/obstacle.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "collision/closed_surface.h"

namespace tissu {

namespace {

// The keyframe segment holding time t: [k, k + 1], or k alone before the first and after
// the last keyframe (then `inside` is false).
struct Segment {
  size_t k = 0;
  bool inside = false;
};

Segment segment_at(const std::vector<Keyframe>& keys, double t) {
  if (keys.empty() || t < keys.front().time) return {0, false};
  for (size_t k = 0; k + 1 < keys.size(); ++k) {
    if (t < keys[k + 1].time) return {k, true};
  }
  return {keys.size() - 1, false};
}

// Angle (rad) times unit axis of the turn from keyframe k to k + 1, the shorter way.
Vec3 turn_between(const Keyframe& a, const Keyframe& b) {
  Eigen::Quaterniond delta = b.rotation * a.rotation.conjugate();
  if (delta.w() < 0.0) delta.coeffs() = -delta.coeffs();
  const Eigen::AngleAxisd turn(delta);
  return turn.angle() * turn.axis();
}

}  // namespace

bool ObstacleMotion::moves_between(double t0, double t1) const {
  if (!velocity.isZero() || (period > 0.0 && !amplitude.isZero())) return true;
  for (size_t k = 0; k + 1 < keyframes.size(); ++k) {
    const Keyframe& a = keyframes[k];
    const Keyframe& b = keyframes[k + 1];
    if (b.time <= t0 || a.time > t1) continue;  // a segment starting at t1 moves it then
    const bool turns = a.rotation.coeffs() != b.rotation.coeffs() &&
                       a.rotation.coeffs() != -b.rotation.coeffs();
    if (a.translation != b.translation || turns) return true;
  }
  return false;
}

bool ObstacleMotion::moves() const {
  const double always = std::numeric_limits<double>::infinity();
  return moves_between(-always, always);
}

Vec3 Obstacle::offset(double t) const {
  Vec3 o = motion.velocity * t;
  if (motion.period > 0.0) o += motion.amplitude * std::sin(2.0 * M_PI * t / motion.period);
  const std::vector<Keyframe>& keys = motion.keyframes;
  if (!keys.empty()) {
    const Segment s = segment_at(keys, t);
    if (s.inside) {
      const double f = (t - keys[s.k].time) / (keys[s.k + 1].time - keys[s.k].time);
      o += (1.0 - f) * keys[s.k].translation + f * keys[s.k + 1].translation;
    } else {
      o += keys[s.k].translation;
    }
  }
  return o;
}

Vec3 Obstacle::velocity(double t) const {
  Vec3 v = motion.velocity;
  if (motion.period > 0.0) {
    const double w = 2.0 * M_PI / motion.period;
    v += motion.amplitude * (w * std::cos(w * t));
  }
  const std::vector<Keyframe>& keys = motion.keyframes;
  const Segment s = segment_at(keys, t);
  if (s.inside) {
    v += (keys[s.k + 1].translation - keys[s.k].translation) /
         (keys[s.k + 1].time - keys[s.k].time);
  }
  return v;
}

Mat3 Obstacle::rotation(double t) const {
  const std::vector<Keyframe>& keys = motion.keyframes;
  if (keys.empty()) return Mat3::Identity();
  const Segment s = segment_at(keys, t);
  if (!s.inside) return keys[s.k].rotation.toRotationMatrix();
  const double f = (t - keys[s.k].time) / (keys[s.k + 1].time - keys[s.k].time);
  const Vec3 turn = turn_between(keys[s.k], keys[s.k + 1]);
  const double angle = turn.norm();
  const Mat3 partial = angle > 0.0 ? Eigen::AngleAxisd(f * angle, turn / angle).toRotationMatrix()
                                   : Mat3::Identity();
  return partial * keys[s.k].rotation.toRotationMatrix();
}

Vec3 Obstacle::angular_velocity(double t) const {
  const std::vector<Keyframe>& keys = motion.keyframes;
  const Segment s = segment_at(keys, t);
  if (!s.inside) return Vec3::Zero();
  return turn_between(keys[s.k], keys[s.k + 1]) / (keys[s.k + 1].time - keys[s.k].time);
}

Vec3 Obstacle::carried(const Vec3& p0, double t) const {
  return center_at(t) + rotation(t) * (p0 - center);
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
  return signed_distance_from(p, center_at(t), normal, rotation(t));
}

double Obstacle::signed_distance_from(const Vec3& p, const Vec3& c, Vec3* normal,
                                      const Mat3& turn, double reach) const {
  switch (kind) {
    case ObstacleKind::Mesh: {
      // In the surface's frame at t = 0; distances are the same there.
      const Vec3 local = center + turn.transpose() * (p - c);
      SurfaceQuery q = surface->closest_within(local, reach);
      if (q.triangle < 0 && q.distance < 0.0) q = surface->closest(local);
      *normal = turn * q.normal;
      return q.distance;
    }
    case ObstacleKind::Sphere: return sphere_distance(p, c, radius, normal);
    case ObstacleKind::Cylinder: return cylinder_distance(p, c, axis, radius, half_length, normal);
    case ObstacleKind::Plane:
      *normal = axis;
      return (p - c).dot(axis);
  }
  return 0.0;
}

SurfacePoint PlacedObstacle::closest(const Vec3& p, double reach) const {
  SurfacePoint s;
  s.distance = obstacle->signed_distance_from(p, center, &s.normal, rotation, reach);
  const Vec3 on_surface = p - s.distance * s.normal;
  s.velocity = velocity + angular_velocity.cross(on_surface - center);
  return s;
}

PlacedObstacle place_obstacle(const Obstacle& obstacle, double t) {
  return PlacedObstacle{&obstacle, obstacle.center_at(t), obstacle.velocity(t),
                        obstacle.rotation(t), obstacle.angular_velocity(t)};
}

const char* obstacle_kind_name(ObstacleKind kind) {
  switch (kind) {
    case ObstacleKind::Sphere: return "sphere";
    case ObstacleKind::Cylinder: return "cylinder";
    case ObstacleKind::Plane: return "plane";
    case ObstacleKind::Mesh: return "mesh";
  }
  return "unknown";
}

}  // namespace tissu
