// The one conversion of the simulation into drawn content: obstacle insets, the surface
// drawn for each kind of obstacle, and the cloth copied as it is.
#include <gtest/gtest.h>

#include "view/drawn_frame.h"

namespace tissu {
namespace {

TEST(ObstacleInset, TwiceTheEdgeSagittaPlusHalfAPercentAtMostAFifth) {
  // R = 0.3 m, L = 0.02 m: 0.0015 + 0.0004 / 1.2 m.
  EXPECT_NEAR(obstacle_inset(0.3, 0.02), 0.0015 + 0.0004 / 1.2, 1e-15);
  EXPECT_NEAR(obstacle_inset(0.01, 0.05), 0.002, 1e-15);  // capped at 20 % of R
  EXPECT_EQ(obstacle_inset(0.0, 0.02), 0.0);               // planes and meshes
}

TEST(DrawnObstacle, SphereIsDrawnAtItsThicknessLessTheInset) {
  Obstacle ob;
  ob.kind = ObstacleKind::Sphere;
  ob.center = Vec3(1, 2, 3);
  ob.radius = 0.3;
  ob.thickness = 0.004;
  const ObstacleShape s = drawn_obstacle(ob, 0.5, 0.001);
  EXPECT_EQ(s.kind, ObstacleShape::Kind::Sphere);
  EXPECT_EQ(s.center, Vec3(1, 2, 3));
  EXPECT_NEAR(s.radius, 0.303, 1e-15);
}

TEST(DrawnObstacle, PlaneIsDrawnTwoMillimetresBelowTheSurfaceClothRestsOn) {
  Obstacle ob;
  ob.kind = ObstacleKind::Plane;
  ob.center = Vec3(0, 0, -0.3);
  ob.axis = Vec3(0, 0, 1);
  ob.thickness = 0.005;
  const ObstacleShape s = drawn_obstacle(ob, 0.0, 0.0);
  EXPECT_EQ(s.kind, ObstacleShape::Kind::Plane);
  EXPECT_NEAR(s.center.z(), -0.3 + 0.003, 1e-15);
}

TEST(DrawnFrame, ClothAsItIsAndObstaclesInsetForTheGivenEdge) {
  Model model;
  model.triangles = {Tri(0, 1, 2)};
  model.rest_uv = {Vec2(0, 0), Vec2(1, 0), Vec2(0, 1)};
  Obstacle sphere;
  sphere.radius = 0.3;
  model.obstacles = {sphere};
  State state;
  state.x = {Vec3(0, 0, 0), Vec3(0.03, 0, 0), Vec3(0, 0.04, 0)};
  EXPECT_NEAR(mean_edge_length(model, state.x), (0.03 + 0.05 + 0.04) / 3.0, 1e-15);
  const FrameContent content = drawn_frame(model, state, 0.02);
  EXPECT_EQ(content.positions, state.x);
  EXPECT_EQ(content.triangles, model.triangles);
  ASSERT_EQ(content.obstacles.size(), 1u);
  EXPECT_NEAR(content.obstacles[0].radius, 0.3 - obstacle_inset(0.3, 0.02), 1e-15);
}

}  // namespace
}  // namespace tissu
