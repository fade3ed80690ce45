// Rigid obstacles the cloth collides with: sphere, finite capped cylinder, plane, and a
// closed triangle surface (mesh). A closed set, so one plain struct and a switch.
// Obstacles may move rigidly: offset(t) = velocity * t + amplitude * sin(2 pi t / period)
// + the translation of keyframes; meshes may also turn about their centre by keyframes.
#pragma once

#include <Eigen/Geometry>
#include <memory>
#include <string>
#include <vector>

#include "core/types.h"

namespace tissu {

class ClosedSurface;  // collision/closed_surface.h

enum class ObstacleKind { Sphere, Cylinder, Plane, Mesh };

// A pose of a keyframed motion: at `time` the obstacle is turned by `rotation` about its
// centre and moved by `translation` from where it is at t = 0. Between two keyframes it
// moves at constant velocity and turns at constant angular velocity about a fixed axis
// (the shorter way); before the first keyframe it holds the first pose, after the last
// one the last.
struct Keyframe {
  double time = 0.0;                // s
  Vec3 translation = Vec3::Zero();  // m
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();
};

struct ObstacleMotion {
  Vec3 velocity = Vec3::Zero();   // m/s, constant drift
  Vec3 amplitude = Vec3::Zero();  // m, periodic displacement amplitude
  double period = 0.0;            // s; 0 = no periodic part
  std::vector<Keyframe> keyframes;  // ascending times; empty = none
  // Whether the pose changes at some time, and whether it changes within [t0, t1] (s), a
  // segment that starts at t1 included (the velocity at t1 is already its own). Keyframes
  // that all hold one pose do not move the obstacle.
  bool moves() const;
  bool moves_between(double t0, double t1) const;
};

// The least distance a mesh obstacle keeps cloth from its surface, m. At a thickness of 0
// a vertex laid on a flat part of the surface ends a step on it, and rounding puts it on
// either side: cloth resting on a mesh crossed it at 3e-10 m in most frames.
constexpr double kMeshThicknessFloor = 1e-6;

struct Obstacle {
  ObstacleKind kind = ObstacleKind::Sphere;
  Vec3 center = Vec3::Zero();  // sphere/cylinder centre, or a point of the plane, at t = 0 (m)
  Vec3 axis = Vec3::UnitZ();   // cylinder axis or plane normal (unit)
  double radius = 0.0;         // sphere/cylinder radius (m)
  double half_length = 0.0;    // cylinder half length along the axis (m)
  double friction = 0.0;       // Coulomb coefficient (dimensionless)
  double thickness = 0.0;      // m: the distance the cloth keeps from the surface
  ObstacleMotion motion;
  // Mesh: the closed surface, in world coordinates at t = 0; `center` is the point it
  // turns about (the centre of its bounding box).
  std::shared_ptr<const ClosedSurface> surface;

  Vec3 offset(double t) const;         // rigid displacement at time t (m)
  Vec3 velocity(double t) const;       // rigid velocity at time t (m/s)
  Vec3 center_at(double t) const { return center + offset(t); }
  Mat3 rotation(double t) const;          // turn about the centre since t = 0 (keyframes)
  Vec3 angular_velocity(double t) const;  // rad/s, world axes
  // Rigid velocity at time t (m/s) of the obstacle's point at world position p (m).
  Vec3 point_velocity(const Vec3& p, double t) const {
    return velocity(t) + angular_velocity(t).cross(p - center_at(t));
  }
  // World position at time t of a point that is at `p0` at t = 0 (moving with the obstacle).
  Vec3 carried(const Vec3& p0, double t) const;

  // Signed distance from p to the surface at time t (m, negative inside) and the
  // outward unit normal of the closest surface point.
  double signed_distance(const Vec3& p, double t, Vec3* normal) const;
  // The same with the centre (or plane point) already placed at center_at(t) and, for a
  // mesh, turned by rotation(t). A mesh answers points outside it and farther than
  // `reach` from it with a lower bound >= reach (the cost of a grid lookup instead of a
  // tree search); inside and within reach the distance is exact.
  double signed_distance_from(const Vec3& p, const Vec3& placed_center, Vec3* normal,
                              const Mat3& rotation = Mat3::Identity(),
                              double reach = INFINITY) const;
};

const char* obstacle_kind_name(ObstacleKind kind);

// The point of an obstacle's surface closest to a given point.
struct SurfacePoint {
  double distance = 0.0;         // signed distance of the given point, m (negative inside)
  Vec3 normal = Vec3::UnitZ();   // outward unit normal
  Vec3 velocity = Vec3::Zero();  // velocity of the surface there, m/s
};

// An obstacle placed at one time: where it is and how it moves then.
struct PlacedObstacle {
  const Obstacle* obstacle = nullptr;
  Vec3 center = Vec3::Zero();    // centre or plane point, m
  Vec3 velocity = Vec3::Zero();  // rigid velocity of the centre, m/s
  Mat3 rotation = Mat3::Identity();      // meshes: turn about the centre since t = 0
  Vec3 angular_velocity = Vec3::Zero();  // rad/s

  // The closest surface point to p (a mesh: exact within `reach` of the surface, a lower
  // bound >= reach beyond it).
  SurfacePoint closest(const Vec3& p, double reach = INFINITY) const;
};

PlacedObstacle place_obstacle(const Obstacle& obstacle, double t);

}  // namespace tissu
