#include "render/draw/shadow_map.h"

#include <gtest/gtest.h>

#include <vector>

#include "render/gl/offscreen_context.h"

namespace tissu {
namespace {

constexpr int kSize = 1024;

// Where `p` falls in the map, in texels from its lower left corner.
glm::vec2 texel_of(const ShadowMap& map, const Vec3& p) {
  const glm::vec4 clip = map.light_matrix() * glm::vec4(float(p.x()), float(p.y()), float(p.z()), 1.0f);
  return {0.5f * (clip.x + 1.0f) * map.width(), 0.5f * (clip.y + 1.0f) * map.height()};
}

// The casters' points lie inside the map, at least the margin the ground's look-up
// needs (three texels) away from its sides.
void expect_inside(const ShadowMap& map, const std::vector<Vec3>& points) {
  for (const Vec3& p : points) {
    const glm::vec2 t = texel_of(map, p);
    EXPECT_GE(t.x, 3.0f);
    EXPECT_GE(t.y, 3.0f);
    EXPECT_LE(t.x, map.width() - 3.0f);
    EXPECT_LE(t.y, map.height() - 3.0f);
  }
}

TEST(render_shadow_map, KeepsOnlyTheTexelsTheCastersCover) {
  OffscreenContext context(16, 16, 1);
  ShadowMap map(kSize);
  // A small patch in one corner of a 1 m box: a small part of the square around the
  // box's bounding sphere.
  const Box3 box(Vec3(0, 0, 0), Vec3(1, 1, 1));
  const std::vector<Vec3> patch = {Vec3(0, 0, 0), Vec3(0.1, 0, 0), Vec3(0, 0.1, 0), Vec3(0.1, 0.1, 0.05)};
  map.begin(Vec3(0.3, 0.2, -1.0), box, patch);
  EXPECT_DOUBLE_EQ(map.texel_size(), 2.04 * 0.5 * box.diagonal().norm() / kSize);
  EXPECT_LT(map.width(), kSize / 4);
  EXPECT_LT(map.height(), kSize / 4);
  EXPECT_EQ(map.width() % 64, 0);
  EXPECT_EQ(map.height() % 64, 0);
  expect_inside(map, patch);
}

TEST(render_shadow_map, HoldsCastersFillingTheirBoundingSphere) {
  OffscreenContext context(16, 16, 1);
  ShadowMap map(kSize);
  const Box3 box(Vec3(-1, -2, 0), Vec3(1, 2, 0.5));
  std::vector<Vec3> corners;
  for (int i = 0; i < 8; ++i) {
    corners.emplace_back(i & 1 ? 1 : -1, i & 2 ? 2 : -2, i & 4 ? 0.5 : 0);
  }
  map.begin(Vec3(0.5, 1.5, -1.75), box, corners);
  EXPECT_LE(map.width(), kSize);
  EXPECT_LE(map.height(), kSize);
  expect_inside(map, corners);
}

}  // namespace
}  // namespace tissu
