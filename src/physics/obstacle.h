// Rigid obstacles the cloth collides with: sphere, finite capped cylinder, plane.
// A closed set, so one plain struct and a switch. Obstacles may move rigidly:
// offset(t) = velocity * t + amplitude * sin(2 pi t / period).
#pragma once

#include <string>

#include "core/types.h"

namespace tissu {

enum class ObstacleKind { Sphere, Cylinder, Plane };

struct ObstacleMotion {
  Vec3 velocity = Vec3::Zero();   // m/s, constant drift
  Vec3 amplitude = Vec3::Zero();  // m, periodic displacement amplitude
  double period = 0.0;            // s; 0 = no periodic part
  bool moves() const { return !velocity.isZero() || (period > 0 && !amplitude.isZero()); }
};

struct Obstacle {
  ObstacleKind kind = ObstacleKind::Sphere;
  Vec3 center = Vec3::Zero();  // sphere/cylinder centre, or a point of the plane, at t = 0 (m)
  Vec3 axis = Vec3::UnitZ();   // cylinder axis or plane normal (unit)
  double radius = 0.0;         // sphere/cylinder radius (m)
  double half_length = 0.0;    // cylinder half length along the axis (m)
  double friction = 0.0;       // Coulomb coefficient (dimensionless)
  ObstacleMotion motion;

  Vec3 offset(double t) const;         // rigid displacement at time t (m)
  Vec3 velocity(double t) const;       // rigid velocity at time t (m/s)
  Vec3 center_at(double t) const { return center + offset(t); }

  // Signed distance from p to the surface at time t (m, negative inside) and the
  // outward unit normal of the closest surface point.
  double signed_distance(const Vec3& p, double t, Vec3* normal) const;
  // The same with the centre (or plane point) already placed: center_at(t).
  double signed_distance_from(const Vec3& p, const Vec3& placed_center, Vec3* normal) const;
};

const char* obstacle_kind_name(ObstacleKind kind);

}  // namespace tissu
