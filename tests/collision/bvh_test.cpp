// The hierarchy's queries against brute force over random boxes.
#include <gtest/gtest.h>

#include <cstdint>
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

// FNV-1a over the sequence of pairs a self-overlap visits.
uint64_t self_pair_sequence_hash(const Bvh& tree, int* count) {
  uint64_t h = 1469598103934665603ull;
  *count = 0;
  tree.for_each_self_overlap([&](int i, int j) {
    for (int v : {i, j}) {
      for (int byte = 0; byte < 4; ++byte) {
        h ^= (static_cast<uint32_t>(v) >> (8 * byte)) & 0xffu;
        h *= 1099511628211ull;
      }
    }
    ++*count;
  });
  return h;
}

// Boxes of the edges of a 60 x 40 grid sheet (1 cm squares, one diagonal each) folded in
// half over itself, its layers 3 mm apart, each grown by 4 mm (a build's regions).
std::vector<Box3> folded_sheet_edge_boxes() {
  constexpr int kNx = 60, kNy = 40;
  constexpr double kCell = 0.01, kGap = 0.003, kGrow = 0.004;  // m
  auto point = [&](int i, int j) {
    const double u = i * kCell, half = 0.5 * kNx * kCell;
    return u <= half ? Vec3(u, j * kCell, 0.0) : Vec3(2.0 * half - u, j * kCell, kGap);
  };
  std::vector<Box3> boxes;
  auto edge = [&](int i0, int j0, int i1, int j1) {
    Box3 b(point(i0, j0));
    b.extend(point(i1, j1));
    boxes.emplace_back(b.min() - Vec3::Constant(kGrow), b.max() + Vec3::Constant(kGrow));
  };
  for (int j = 0; j <= kNy; ++j) {
    for (int i = 0; i <= kNx; ++i) {
      if (i < kNx) edge(i, j, i + 1, j);
      if (j < kNy) edge(i, j, i, j + 1);
      if (i < kNx && j < kNy) edge(i, j, i + 1, j + 1);
    }
  }
  return boxes;
}

// The order in which self-overlap visits its pairs is that of the full double loop over
// every pair of leaves (the values below are that traversal's, before its leaves were
// pruned against each other's boxes). The collision stage puts the pairs it is given in
// an order of its own, so its bits no longer depend on this one.
TEST(Bvh, SelfPairsKeepTheirOrder) {
  std::vector<Box3> boxes = random_boxes(1500, 7);
  for (Box3& b : boxes) b = Box3(b.min() - Vec3::Constant(0.4), b.max() + Vec3::Constant(0.4));
  Bvh tree;
  tree.build(boxes, 6);
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> shift(-0.3, 0.3);
  for (Box3& b : boxes) b.translate(Vec3(shift(rng), shift(rng), shift(rng)));
  tree.refit(boxes);
  int count = 0;
  const uint64_t random_hash = self_pair_sequence_hash(tree, &count);
  EXPECT_EQ(count, 10385);
  EXPECT_EQ(random_hash, 5120118690118192179ull);

  Bvh sheet;
  sheet.build(folded_sheet_edge_boxes(), 6);
  const uint64_t sheet_hash = self_pair_sequence_hash(sheet, &count);
  EXPECT_EQ(count, 106757);
  EXPECT_EQ(sheet_hash, 6718548508419488741ull);
}

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
