// Camera and light matrices (glm, single precision for the GPU).
#pragma once

#include <glm/glm.hpp>

#include "core/types.h"
#include "render/camera.h"

namespace tissu {

inline glm::vec3 to_glm(const Vec3& v) {
  return glm::vec3(static_cast<float>(v.x()), static_cast<float>(v.y()), static_cast<float>(v.z()));
}

glm::mat4 view_matrix(const Camera& camera);

// Perspective projection whose near and far planes enclose `points` (world) seen by `camera`.
glm::mat4 projection_matrix(const Camera& camera, double aspect, const std::vector<Vec3>& points);

// Rotation taking +z to the unit vector `axis`.
glm::mat3 rotation_from_z(const glm::vec3& axis);

}  // namespace tissu
