// Quality measures on meshes whose answers are known by hand.
#include "mesh/quality.h"

#include <gtest/gtest.h>

#include <cmath>

namespace tissu {
namespace {

TriMesh flat(const Vec2List& uv, const TriList& triangles) {
  TriMesh mesh;
  for (const Vec2& p : uv) mesh.positions.emplace_back(p.x(), p.y(), 0.0);
  mesh.rest_uv = uv;
  mesh.triangles = triangles;
  return mesh;
}

TEST(meshQuality, EquilateralTriangle) {
  const MeshQuality q = measure_quality(flat({{0, 0}, {1, 0}, {0.5, std::sqrt(3.0) / 2}}, {{0, 1, 2}}));
  EXPECT_NEAR(q.min_angle_deg, 60, 1e-9);
  EXPECT_NEAR(q.max_angle_deg, 60, 1e-9);
  EXPECT_NEAR(q.max_aspect_ratio, 1, 1e-12);
  EXPECT_NEAR(q.mean_angle_deviation_deg, 0, 1e-9);
  EXPECT_NEAR(q.total_area, std::sqrt(3.0) / 4, 1e-15);  // m^2
}

TEST(meshQuality, NeedleWithLegsOneToHundred) {
  const MeshQuality q = measure_quality(flat({{0, 0}, {1, 0}, {0, 0.01}}, {{0, 1, 2}}));
  EXPECT_NEAR(q.max_angle_deg, 90, 1e-9);
  EXPECT_NEAR(q.max_aspect_ratio, 1.0001 * std::sqrt(3.0) / 0.02, 1e-9);  // about 87
  EXPECT_NEAR(q.min_area, 0.005, 1e-15);
}

// A hexagon fan: one interior vertex of valence 6, six boundary vertices.
TEST(meshQuality, ValenceAndBoundaryOfAHexagonFan) {
  Vec2List uv{{0, 0}};
  TriList triangles;
  for (int k = 0; k < 6; ++k) {
    uv.emplace_back(std::cos(k * M_PI / 3), std::sin(k * M_PI / 3));
    triangles.emplace_back(0, 1 + k, 1 + (k + 1) % 6);
  }
  const TriMesh mesh = flat(uv, triangles);
  const MeshQuality q = measure_quality(mesh);
  ASSERT_EQ(q.interior_valence_histogram.size(), 7u);
  EXPECT_EQ(q.interior_valence_histogram[6], 1);
  EXPECT_EQ(q.interior_valence6_fraction, 1.0);
  EXPECT_EQ(boundary_edges(mesh.triangles).size(), 6u);
  for (const auto& [a, b] : boundary_edges(mesh.triangles)) {
    EXPECT_NE(a, 0);
    EXPECT_EQ(b, 1 + a % 6);  // in the triangle's (counter-clockwise) order
  }
  // 12 edges in 3 directions (0, 60, 120 deg): all in the 4 fullest bins.
  EXPECT_EQ(q.edge_direction_concentration, 1.0);
}

}  // namespace
}  // namespace tissu
