#include "figure/obstacle_shape.h"

namespace tissu {

ObstacleShape drawn_obstacle(const Obstacle& ob, double t, double inset) {
  ObstacleShape s;
  switch (ob.kind) {
    case ObstacleKind::Sphere: s.kind = ObstacleShape::Kind::Sphere; break;
    case ObstacleKind::Cylinder: s.kind = ObstacleShape::Kind::Cylinder; break;
    case ObstacleKind::Plane: s.kind = ObstacleShape::Kind::Plane; break;
  }
  s.center = ob.center_at(t);
  s.axis = ob.axis;
  s.radius = ob.radius - inset;
  s.half_length = ob.half_length - inset;
  if (ob.kind == ObstacleKind::Plane) s.center -= 0.002 * ob.axis;  // m
  return s;
}

}  // namespace tissu
