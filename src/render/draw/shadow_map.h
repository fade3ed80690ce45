// Depth map seen from the key light (orthographic, a directional light), used to
// darken the ground where cloth or obstacles block that light.
#pragma once

#include <vector>

#include <glm/glm.hpp>

#include "render/gl/gl_objects.h"
#include "render/scene_bounds.h"

namespace tissu {

class ShadowMap {
 public:
  // `size` texels across the casters' bounding sphere at most.
  explicit ShadowMap(int size);

  // Fits the light's view around the casters for light travelling along `direction`,
  // binds the depth framebuffer and clears it. Draw casters after. The texel size is
  // that of `size` texels across the bounding sphere of `casters`; the map covers only
  // the part of that square that `points` (whose convex hull holds every caster) cover
  // as the light sees them, plus a margin, so fewer texels are cleared and drawn.
  void begin(const Vec3& direction, const Box3& casters, const std::vector<Vec3>& points);

  // World position -> light clip space ([-1, 1]^3 inside the map): for drawing the casters.
  const glm::mat4& light_matrix() const { return light_matrix_; }
  // The same for the receivers' look-up, with each point moved `bias` m towards the light:
  // casters within that distance of a receiver (cloth resting on the ground) do not shadow
  // it. A distance, so the same at any size of the map (a slope-scaled polygon offset
  // grows with the texel and let the shadow of cloth near the ground vanish in small maps).
  glm::mat4 lookup_matrix(double bias) const;
  GLuint texture() const { return depth_.get(); }
  // Side of one texel, m (this frame's).
  double texel_size() const { return texel_; }
  // Texels across and down this frame (at most size() each).
  int width() const { return width_; }
  int height() const { return height_; }

 private:
  void allocate(int width, int height);

  int size_;
  int width_ = 0, height_ = 0;  // allocated texels
  double texel_ = 0.0;          // m
  double depth_range_ = 1.0;    // m, from the near to the far plane of the light's view
  GlTexture depth_;
  GlFramebuffer framebuffer_;
  glm::mat4 light_matrix_{1.0f};
};

}  // namespace tissu
