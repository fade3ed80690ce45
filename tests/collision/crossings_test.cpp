// The exact crossing check: separate, piercing and touching triangles, neighbours that
// share a vertex or an edge, whole meshes.
#include <gtest/gtest.h>

#include "collision/crossings.h"

namespace tissu {
namespace {

TEST(Crossings, SeparatePiercingAndTouching) {
  const Vec3List x = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0},          // flat triangle 0
                      {0.2, 0.2, -1}, {0.3, 0.2, 1}, {0.2, 0.3, 1},  // pierces it
                      {5, 5, 5}, {6, 5, 5}, {5, 6, 5}};          // far away
  EXPECT_EQ(self_crossings(x, {{0, 1, 2}, {3, 4, 5}}).count, 1u);
  EXPECT_EQ(self_crossings(x, {{0, 1, 2}, {6, 7, 8}}).count, 0u);
  // Touching: a corner exactly on the face.
  const Vec3List y = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.25, 0.25, 0}, {1, 1, 1}, {0, 1, 1}};
  EXPECT_EQ(self_crossings(y, {{0, 1, 2}, {3, 4, 5}}).count, 1u);
  // The same just above: apart.
  const Vec3List z = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.25, 0.25, 1e-15}, {1, 1, 1}, {0, 1, 1}};
  EXPECT_EQ(self_crossings(z, {{0, 1, 2}, {3, 4, 5}}).count, 0u);
}

TEST(Crossings, NeighboursSharingAVertex) {
  // Triangle (0, 1, 2) in z = 0; (0, 3, 4) shares vertex 0.
  Vec3List x = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.5, 0.5, 1}, {0.5, 0.5, -1}};
  // Edge 3-4 passes through (0.5, 0.5, 0): outside triangle 0-1-2 (x + y = 1 is its edge:
  // on it, so they touch).
  EXPECT_EQ(self_crossings(x, {{0, 1, 2}, {0, 3, 4}}).count, 1u);
  x[3] = {0.3, 0.3, 1};
  x[4] = {0.3, 0.3, -1};  // edge 3-4 pierces the face
  EXPECT_EQ(self_crossings(x, {{0, 1, 2}, {0, 3, 4}}).count, 1u);
  x[3] = {0.7, 0.7, 1};
  x[4] = {0.7, 0.7, -1};  // edge 3-4 passes beside, but the triangle cuts the face along x = y
  EXPECT_EQ(self_crossings(x, {{0, 1, 2}, {0, 3, 4}}).count, 1u);
  x[3] = {-0.5, -0.5, 1};
  x[4] = {-0.5, 0.2, -1};  // meets the plane z = 0 only at x < 0: beside the face
  EXPECT_EQ(self_crossings(x, {{0, 1, 2}, {0, 3, 4}}).count, 0u);
  // A fan around vertex 0 in the plane: neighbours, no crossing.
  x[3] = {-1, 0.5, 0};
  x[4] = {-1, -1, 0};
  EXPECT_EQ(self_crossings(x, {{0, 1, 2}, {0, 2, 3}, {0, 3, 4}}).count, 0u);
  // The second triangle lies in the plane over the first's corner: they overlap.
  x[3] = {0.5, 0.1, 0};
  x[4] = {0.1, 0.5, 0};
  EXPECT_EQ(self_crossings(x, {{0, 1, 2}, {0, 3, 4}}).count, 1u);
}

TEST(Crossings, NeighboursSharingAnEdge) {
  Vec3List x = {{0, 0, 0}, {1, 0, 0}, {0.5, 1, 0}, {0.5, -1, 0}};
  const TriList t = {{0, 1, 2}, {1, 0, 3}};
  EXPECT_EQ(self_crossings(x, t).count, 0u);  // flat sheet
  x[3] = {0.5, 0.5, 0.5};
  EXPECT_EQ(self_crossings(x, t).count, 0u);  // folded at an angle
  x[3] = {0.5, 0.5, 0};
  EXPECT_EQ(self_crossings(x, t).count, 1u);  // folded flat onto each other
}

TEST(Crossings, MeshesAndLimits) {
  // A strip of 10 x 1 cells folded back over itself at x = 5: the folded part passes
  // through the lower part at height 0 (it goes from z = 0.5 down to z = -0.5).
  Vec3List x;
  TriList t;
  for (int i = 0; i <= 10; ++i) {
    for (int j = 0; j <= 1; ++j) {
      const double s = i <= 5 ? i : 10 - i;
      const double z = i <= 5 ? 0.0 : 0.5 - 0.2 * (i - 5);
      x.emplace_back(s + 0.01 * i, j + 0.1, z);
    }
  }
  for (int i = 0; i < 10; ++i) {
    t.emplace_back(2 * i, 2 * i + 2, 2 * i + 3);
    t.emplace_back(2 * i, 2 * i + 3, 2 * i + 1);
  }
  const CrossingReport all = self_crossings(x, t);
  EXPECT_GT(all.count, 0u);
  const CrossingReport one = self_crossings(x, t, 1);
  EXPECT_EQ(one.count, 1u);
  // Against a second mesh: a plane far below meets nothing, one through the strip does.
  const Vec3List plane = {{-10, -10, -3}, {10, -10, -3}, {0, 10, -3}};
  EXPECT_EQ(crossings_between(x, t, plane, {{0, 1, 2}}).count, 0u);
  const Vec3List through = {{-10, -10, -0.1}, {30, -10, 0.05}, {0, 30, 0.05}};
  EXPECT_GT(crossings_between(x, t, through, {{0, 1, 2}}).count, 0u);
}

}  // namespace
}  // namespace tissu
