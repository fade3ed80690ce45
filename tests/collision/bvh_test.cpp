// The hierarchy's queries against brute force over random boxes.
#include <gtest/gtest.h>

#include <random>
#include <set>

#include "collision/bvh.h"

namespace tissu {
namespace {

std::vector<Box3> random_boxes(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> pos(0, 10), size(0, 0.6);
  std::vector<Box3> boxes;
  for (int i = 0; i < n; ++i) {
    const Vec3 lo(pos(rng), pos(rng), pos(rng));
    boxes.emplace_back(lo, lo + Vec3(size(rng), size(rng), size(rng)));
  }
  return boxes;
}

TEST(Bvh, OverlapsMatchBruteForce) {
  const std::vector<Box3> boxes = random_boxes(700, 1);
  Bvh tree;
  tree.build(boxes);
  const std::vector<Box3> queries = random_boxes(50, 2);
  for (const Box3& q : queries) {
    std::set<int> found, expected;
    tree.for_each_overlap(q, [&](int i) { EXPECT_TRUE(found.insert(i).second); });
    for (int i = 0; i < 700; ++i) {
      if (boxes[i].intersects(q)) expected.insert(i);
    }
    EXPECT_EQ(found, expected);
  }
}

class BvhLeaves : public ::testing::TestWithParam<int> {};

TEST_P(BvhLeaves, SelfAndCrossPairsMatchBruteForceAfterRefit) {
  std::vector<Box3> boxes = random_boxes(500, 3);
  Bvh tree;
  tree.build(boxes, GetParam());
  // Move every box: refit keeps the answers exact.
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> shift(-1, 1);
  for (Box3& b : boxes) b.translate(Vec3(shift(rng), shift(rng), shift(rng)));
  tree.refit(boxes);
  std::set<std::pair<int, int>> found, expected;
  tree.for_each_self_overlap([&](int i, int j) {
    EXPECT_NE(i, j);
    EXPECT_TRUE(found.insert({std::min(i, j), std::max(i, j)}).second);
  });
  for (int i = 0; i < 500; ++i) {
    for (int j = i + 1; j < 500; ++j) {
      if (boxes[i].intersects(boxes[j])) expected.insert({i, j});
    }
  }
  EXPECT_EQ(found, expected);

  const std::vector<Box3> others = random_boxes(300, 5);
  Bvh other;
  other.build(others, 7 - GetParam());
  std::set<std::pair<int, int>> cross, cross_expected;
  tree.for_each_overlap_with(other, [&](int i, int j) { EXPECT_TRUE(cross.insert({i, j}).second); });
  for (int i = 0; i < 500; ++i) {
    for (int j = 0; j < 300; ++j) {
      if (boxes[i].intersects(others[j])) cross_expected.insert({i, j});
    }
  }
  EXPECT_EQ(cross, cross_expected);
}

INSTANTIATE_TEST_SUITE_P(LeafSizes, BvhLeaves, ::testing::Values(1, 2, 3, 6));

TEST(Bvh, NearestMatchesBruteForce) {
  const std::vector<Box3> boxes = random_boxes(400, 6);
  Bvh tree;
  tree.build(boxes);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> pos(-2, 12);
  // Primitive = the box's centre point.
  auto distance2 = [&](int i, const Vec3& p) { return (boxes[i].center() - p).squaredNorm(); };
  for (int trial = 0; trial < 100; ++trial) {
    const Vec3 p(pos(rng), pos(rng), pos(rng));
    double best2 = 0;
    const int found = tree.nearest(p, INFINITY, distance2, &best2);
    int expected = -1;
    double expected2 = INFINITY;
    for (int i = 0; i < 400; ++i) {
      if (distance2(i, p) < expected2) {
        expected2 = distance2(i, p);
        expected = i;
      }
    }
    EXPECT_EQ(found, expected);
    EXPECT_EQ(best2, expected2);
    // Bounded: nothing within a radius below the nearest distance.
    EXPECT_EQ(tree.nearest(p, expected2 * 0.99, distance2, &best2), -1);
  }
}

}  // namespace
}  // namespace tissu
