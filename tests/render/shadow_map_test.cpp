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

// Clip-space depth of `p` (world) through `m`.
float clip_depth(const glm::mat4& m, const Vec3& p) {
  const glm::vec4 clip = m * glm::vec4(float(p.x()), float(p.y()), float(p.z()), 1.0f);
  return clip.z / clip.w;
}

TEST(render_shadow_map, LookupBiasIsADistanceTowardsTheLight) {
  OffscreenContext context(16, 16, 1);
  const Box3 box(Vec3(-1, -1, 0), Vec3(1, 1, 0.5));
  const std::vector<Vec3> points = {box.min(), box.max()};
  const Vec3 direction(0.5, 1.5, -1.75);
  const Vec3 p(0.3, -0.2, 0.0);
  const double bias = 0.002;  // m
  for (int size : {512, 896, 1024}) {
    ShadowMap map(size);
    map.begin(direction, box, points);
    // The look-up sees p where the casters' matrix sees p moved `bias` towards the light.
    EXPECT_NEAR(clip_depth(map.lookup_matrix(bias), p),
                clip_depth(map.light_matrix(), p - bias * direction.normalized()), 1e-6)
        << size;
    EXPECT_EQ(clip_depth(map.lookup_matrix(0.0), p), clip_depth(map.light_matrix(), p));
  }
}

}  // namespace
}  // namespace tissu
