// What one frame shows, in world coordinates (metres, z up). The renderer has its
// own obstacle description so that it does not depend on the physics library; the
// caller converts physics Obstacles (at the frame's time) into ObstacleShapes.
#pragma once

#include <Eigen/Geometry>
#include <memory>
#include <string>
#include <vector>

#include "core/types.h"

namespace tissu {

struct ObstacleShape {
  enum class Kind { Sphere, Cylinder, Plane, Mesh };
  Kind kind = Kind::Sphere;
  Vec3 center = Vec3::Zero();  // sphere/cylinder centre, any point of the plane, or where
                               // the mesh's pivot is now (m)
  Vec3 axis = Vec3::UnitZ();   // cylinder axis or plane normal (need not be unit)
  double radius = 0.0;         // sphere/cylinder radius (m)
  double half_length = 0.0;    // cylinder half length along the axis (m)
  // Mesh: a closed surface given at its first pose (m), drawn turned by `rotation` about
  // `pivot` and moved so that the pivot is at `center`. The vertex list identifies the
  // surface: the renderer uploads it once.
  std::shared_ptr<const Vec3List> mesh_vertices;
  std::shared_ptr<const TriList> mesh_triangles;
  Eigen::AlignedBox3d mesh_bounds;  // of mesh_vertices
  Vec3 pivot = Vec3::Zero();
  Mat3 rotation = Mat3::Identity();
};

struct FrameContent {
  Vec3List positions;  // cloth vertex positions (m)
  Vec2List rest_uv;    // cloth rest-state coordinates (m), one per vertex; drives the fabric pattern
  TriList triangles;   // counter-clockwise seen from the front side
  std::vector<ObstacleShape> obstacles;
  std::vector<std::string> overlay_lines;  // drawn in the bottom-left corner, first line on top
};

// The corner text for `info: true`: integrator, triangle count and simulated time.
std::vector<std::string> info_overlay_lines(const std::string& integrator, size_t triangle_count,
                                            double time_s);

}  // namespace tissu
