#include "figure/obstacle_shape.h"

#include "collision/closed_surface.h"

namespace tissu {

ObstacleShape drawn_obstacle(const Obstacle& ob, double t, double inset) {
  ObstacleShape s;
  switch (ob.kind) {
    case ObstacleKind::Sphere: s.kind = ObstacleShape::Kind::Sphere; break;
    case ObstacleKind::Cylinder: s.kind = ObstacleShape::Kind::Cylinder; break;
    case ObstacleKind::Plane: s.kind = ObstacleShape::Kind::Plane; break;
    case ObstacleKind::Mesh: s.kind = ObstacleShape::Kind::Mesh; break;
  }
  s.center = ob.center_at(t);
  s.axis = ob.axis;
  // Cloth keeps the obstacle's thickness from its surface: the surface drawn is the one the
  // cloth rests on.
  s.radius = ob.radius + ob.thickness - inset;
  s.half_length = ob.half_length + ob.thickness - inset;
  if (ob.kind == ObstacleKind::Plane) s.center += (ob.thickness - 0.002) * ob.axis.normalized();  // m
  if (ob.kind == ObstacleKind::Mesh) {
    // Drawn as it is (its triangles are the surface the cloth meets, no tessellation).
    s.mesh_vertices = std::shared_ptr<const Vec3List>(ob.surface, &ob.surface->vertices());
    s.mesh_triangles = std::shared_ptr<const TriList>(ob.surface, &ob.surface->triangles());
    s.mesh_bounds = ob.surface->bounds();
    s.pivot = ob.center;
    s.rotation = ob.rotation(t);
  }
  return s;
}

}  // namespace tissu
