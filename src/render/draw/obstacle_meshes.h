// Unit shapes the obstacles are drawn with, and the model matrices that place them.
#pragma once

#include <glm/glm.hpp>

#include "render/frame_content.h"
#include "render/gl/mesh_buffer.h"

namespace tissu {

IndexedMesh unit_sphere(int slices, int stacks);  // radius 1 at the origin
IndexedMesh unit_cylinder(int slices);            // radius 1, z in [-1, 1], capped
IndexedMesh unit_square();                        // [-1, 1]^2 in z = 0, normal +z
// A mesh obstacle's surface, smooth-shaded except across edges sharper than 40 degrees.
IndexedMesh surface_mesh(const Vec3List& vertices, const TriList& triangles);

// Model matrix for the unit shape of `shape`. Planes become squares of half size
// `plane_half_size` centred on the point of the plane closest to `plane_focus`.
glm::mat4 obstacle_model(const ObstacleShape& shape, const glm::vec3& plane_focus,
                         float plane_half_size);

}  // namespace tissu
