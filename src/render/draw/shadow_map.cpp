#include "render/draw/shadow_map.h"

#include <glm/gtc/matrix_transform.hpp>

#include "render/draw/view_math.h"
#include "render/render_error.h"

namespace tissu {

ShadowMap::ShadowMap(int size) : size_(size), depth_(make_texture()), framebuffer_(make_framebuffer()) {
  glBindTexture(GL_TEXTURE_2D, depth_.get());
  glTexImage2D(GL_TEXTURE_2D, 0, GL_DEPTH_COMPONENT24, size, size, 0, GL_DEPTH_COMPONENT,
               GL_UNSIGNED_INT, nullptr);
  // Hardware depth comparison with bilinear filtering of the results: soft 1-texel edges.
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_.get());
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, depth_.get(), 0);
  glDrawBuffer(GL_NONE);
  glReadBuffer(GL_NONE);
  if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
    throw RenderError("shadow map: depth framebuffer incomplete");
  }
  check_gl("shadow map: creating");
}

void ShadowMap::begin(const Vec3& direction, const Box3& casters) {
  const Vec3 centre = casters.center();
  const double radius = std::max(0.5 * casters.diagonal().norm(), 1e-3);
  const Vec3 travel = direction.normalized();
  // Light "eye" outside the casters' bounding sphere, looking along the light.
  const Vec3 eye = centre - travel * (2.0 * radius);
  Vec3 up = Vec3::UnitZ();
  if (std::abs(travel.dot(up)) > 0.99) up = Vec3::UnitY();
  const glm::mat4 view = glm::lookAt(to_glm(eye), to_glm(centre), to_glm(up));
  const float r = static_cast<float>(radius * 1.02);
  const glm::mat4 projection = glm::ortho(-r, r, -r, r, static_cast<float>(radius * 0.5),
                                          static_cast<float>(radius * 3.5));
  light_matrix_ = projection * view;

  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_.get());
  glViewport(0, 0, size_, size_);
  glClearDepth(1.0);
  glClear(GL_DEPTH_BUFFER_BIT);
}

}  // namespace tissu
