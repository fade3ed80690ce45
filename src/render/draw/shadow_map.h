// Depth map seen from the key light (orthographic, a directional light), used to
// darken the ground where cloth or obstacles block that light.
#pragma once

#include <glm/glm.hpp>

#include "render/gl/gl_objects.h"
#include "render/scene_bounds.h"

namespace tissu {

class ShadowMap {
 public:
  explicit ShadowMap(int size);

  // Fits the light's view box around `casters` for light travelling along
  // `direction`, binds the depth framebuffer and clears it. Draw casters after.
  void begin(const Vec3& direction, const Box3& casters);

  // World position -> light clip space ([-1, 1]^3 inside the map).
  const glm::mat4& light_matrix() const { return light_matrix_; }
  GLuint texture() const { return depth_.get(); }
  int size() const { return size_; }

 private:
  int size_;
  GlTexture depth_;
  GlFramebuffer framebuffer_;
  glm::mat4 light_matrix_{1.0f};
};

}  // namespace tissu
