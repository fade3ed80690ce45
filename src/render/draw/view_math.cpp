#include "render/draw/view_math.h"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>

namespace tissu {

glm::mat4 view_matrix(const Camera& camera) {
  const Vec3 forward = (camera.target - camera.eye).normalized();
  Vec3 up = camera.up - camera.up.dot(forward) * forward;
  if (up.norm() < 1e-6) up = forward.unitOrthogonal();  // up along the view: any will do
  return glm::lookAt(to_glm(camera.eye), to_glm(camera.target), to_glm(up.normalized()));
}

glm::mat4 projection_matrix(const Camera& camera, double aspect, const std::vector<Vec3>& points) {
  const Vec3 forward = (camera.target - camera.eye).normalized();
  double nearest = 1e300, farthest = 0.0;
  for (const Vec3& p : points) {
    const double depth = (p - camera.eye).dot(forward);
    nearest = std::min(nearest, depth);
    farthest = std::max(farthest, depth);
  }
  const double view_distance = (camera.target - camera.eye).norm();
  const double far_plane = std::max(farthest, view_distance) * 1.05 + 1e-3;
  // 24-bit depth resolves about depth^2 / (near * 2^24): keep near as far out as allowed.
  const double near_plane = std::max(far_plane / 5000.0, 0.9 * nearest);
  return glm::perspective(static_cast<float>(glm::radians(camera.fov_deg)),
                          static_cast<float>(aspect), static_cast<float>(near_plane),
                          static_cast<float>(far_plane));
}

glm::mat3 rotation_from_z(const glm::vec3& axis) {
  const glm::vec3 z = glm::normalize(axis);
  // Any x perpendicular to z, chosen away from the axis nearest to z for accuracy.
  const glm::vec3 helper = std::abs(z.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
  const glm::vec3 x = glm::normalize(glm::cross(helper, z));
  const glm::vec3 y = glm::cross(z, x);
  return glm::mat3(x, y, z);
}

}  // namespace tissu
