#include "view/drawn_frame.h"

#include <algorithm>

#include "collision/closed_surface.h"

namespace tissu {

double mean_edge_length(const Model& model, const Vec3List& x) {
  double sum = 0.0;
  for (const Tri& t : model.triangles) {
    sum += (x[t[0]] - x[t[1]]).norm() + (x[t[1]] - x[t[2]]).norm() + (x[t[2]] - x[t[0]]).norm();
  }
  return model.triangles.empty() ? 0.0 : sum / (3.0 * model.triangles.size());
}

double obstacle_inset(double radius, double edge_length) {
  return std::min(0.2 * radius, 0.005 * radius + edge_length * edge_length / (4.0 * radius));
}

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

std::vector<ObstacleShape> drawn_obstacles(const Model& model, double t, double edge_length) {
  std::vector<ObstacleShape> shapes;
  shapes.reserve(model.obstacles.size());
  for (const Obstacle& ob : model.obstacles) {
    shapes.push_back(drawn_obstacle(ob, t, obstacle_inset(ob.radius, edge_length)));
  }
  return shapes;
}

FrameContent drawn_frame(const Model& model, const State& state, double edge_length) {
  FrameContent content;
  content.triangles = model.triangles;
  content.rest_uv = model.rest_uv;
  content.positions = state.x;
  content.obstacles = drawn_obstacles(model, state.t, edge_length);
  return content;
}

}  // namespace tissu
