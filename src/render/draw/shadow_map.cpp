#include "render/draw/shadow_map.h"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

#include "render/draw/view_math.h"
#include "render/render_error.h"

namespace tissu {

namespace {

// Texels kept around the casters' own texels: the ground's look-up footprint reaches three
// texels past their shadow, and those reads must land on cleared texels inside the map.
constexpr int kMarginTexels = 4;
// The map's sides are rounded up to whole llvmpipe tiles, which also keeps the texture
// from being reallocated for every small move of the casters.
constexpr int kTileTexels = 64;

int round_up_to_tile(int texels) { return (texels + kTileTexels - 1) / kTileTexels * kTileTexels; }

// Texels [first, first + count) of today's grid along one axis that cover [lo, hi] (light
// view coordinates, m, origin at the grid's centre), with the margin, inside [0, size).
void fit_axis(double lo, double hi, double texel, int size, int& first, int& count) {
  const double origin = -0.5 * size * texel;
  const int a = std::max(0, static_cast<int>(std::floor((lo - origin) / texel)) - kMarginTexels);
  const int b = std::min(size, static_cast<int>(std::ceil((hi - origin) / texel)) + kMarginTexels);
  count = std::min(size, round_up_to_tile(std::max(b - a, 1)));
  first = std::min(a, size - count);
}

}  // namespace

ShadowMap::ShadowMap(int size) : size_(size), depth_(make_texture()), framebuffer_(make_framebuffer()) {
  allocate(size, size);
  glBindTexture(GL_TEXTURE_2D, depth_.get());
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

void ShadowMap::allocate(int width, int height) {
  if (width == width_ && height == height_) return;
  glBindTexture(GL_TEXTURE_2D, depth_.get());
  glTexImage2D(GL_TEXTURE_2D, 0, GL_DEPTH_COMPONENT24, width, height, 0, GL_DEPTH_COMPONENT,
               GL_UNSIGNED_INT, nullptr);
  width_ = width;
  height_ = height;
}

void ShadowMap::begin(const Vec3& direction, const Box3& casters, const std::vector<Vec3>& points) {
  const Vec3 centre = casters.center();
  const double radius = std::max(0.5 * casters.diagonal().norm(), 1e-3);
  const Vec3 travel = direction.normalized();
  // Light "eye" outside the casters' bounding sphere, looking along the light.
  const Vec3 eye = centre - travel * (2.0 * radius);
  Vec3 up = Vec3::UnitZ();
  if (std::abs(travel.dot(up)) > 0.99) up = Vec3::UnitY();
  const glm::mat4 view = glm::lookAt(to_glm(eye), to_glm(centre), to_glm(up));
  // The grid of `size_` texels across the bounding sphere (with 2% to spare), of which the
  // map keeps the texels the casters' points cover as the light sees them.
  texel_ = 2.04 * radius / size_;
  glm::vec2 lo(std::numeric_limits<float>::max()), hi(std::numeric_limits<float>::lowest());
  for (const Vec3& p : points) {
    const glm::vec4 v = view * glm::vec4(to_glm(p), 1.0f);
    lo = glm::min(lo, glm::vec2(v));
    hi = glm::max(hi, glm::vec2(v));
  }
  if (points.empty()) lo = -(hi = glm::vec2(static_cast<float>(radius)));
  int first_x = 0, first_y = 0, width = size_, height = size_;
  fit_axis(lo.x, hi.x, texel_, size_, first_x, width);
  fit_axis(lo.y, hi.y, texel_, size_, first_y, height);
  allocate(width, height);
  const double origin = -0.5 * size_ * texel_;
  const auto edge = [&](int texel) { return static_cast<float>(origin + texel * texel_); };
  const glm::mat4 projection =
      glm::ortho(edge(first_x), edge(first_x + width), edge(first_y), edge(first_y + height),
                 static_cast<float>(radius * 0.5), static_cast<float>(radius * 3.5));
  light_matrix_ = projection * view;
  depth_range_ = 3.0 * radius;

  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_.get());
  glViewport(0, 0, width_, height_);
  glClearDepth(1.0);
  glClear(GL_DEPTH_BUFFER_BIT);
}

glm::mat4 ShadowMap::lookup_matrix(double bias) const {
  // Clip-space depth runs from -1 at the near plane to 1 at the far plane.
  glm::mat4 towards_light(1.0f);
  towards_light[3][2] = static_cast<float>(-2.0 * bias / depth_range_);
  return towards_light * light_matrix_;
}

}  // namespace tissu
