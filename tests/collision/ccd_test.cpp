// Continuous collision detection: known crossings, near misses, and random trajectories
// against dense sampling of the step.
#include <gtest/gtest.h>

#include <random>

#include "collision/ccd.h"
#include "collision/primitive_distance.h"

namespace tissu {
namespace {

constexpr double kEta = 1e-9;  // m

TEST(Ccd, VertexFallsThroughTriangle) {
  const Vec3 start[4] = {{0.2, 0.2, 1}, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  const Vec3 end[4] = {{0.2, 0.2, -1}, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  const auto impact = vertex_triangle_impact(start, end, kEta);
  ASSERT_TRUE(impact);
  EXPECT_NEAR(impact->time, 0.5, 1e-12);
  EXPECT_TRUE(impact->normal.isApprox(Vec3(0, 0, 1)));  // the side the vertex came from
  EXPECT_DOUBLE_EQ(impact->weights[0], 1.0);
  EXPECT_NEAR(impact->weights[1], -0.6, 1e-9);
  EXPECT_NEAR(impact->weights[2], -0.2, 1e-9);
  EXPECT_NEAR(impact->weights[3], -0.2, 1e-9);
}

TEST(Ccd, VertexBesideTriangleDoesNotHit) {
  const Vec3 start[4] = {{0.6, 0.6, 1}, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  const Vec3 end[4] = {{0.6, 0.6, -1}, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  EXPECT_FALSE(vertex_triangle_impact(start, end, kEta));
}

TEST(Ccd, TriangleSweepsOverVertex) {
  const Vec3 start[4] = {{0.1, 0.1, 0}, {0, 0, 1}, {1, 0, 1}, {0, 1, 1}};
  const Vec3 end[4] = {{0.1, 0.1, 0}, {0, 0, -3}, {1, 0, -3}, {0, 1, -3}};
  const auto impact = vertex_triangle_impact(start, end, kEta);
  ASSERT_TRUE(impact);
  EXPECT_NEAR(impact->time, 0.25, 1e-12);
  EXPECT_TRUE(impact->normal.isApprox(Vec3(0, 0, -1)));
}

TEST(Ccd, VertexSlidingInThePlaneIsFound) {
  // Coplanar throughout: the cubic vanishes identically.
  const Vec3 start[4] = {{-1, 0.2, 0}, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  const Vec3 end[4] = {{0.5, 0.2, 0}, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  EXPECT_TRUE(vertex_triangle_impact(start, end, kEta));
}

TEST(Ccd, CrossingEdges) {
  const Vec3 start[4] = {{-1, 0.3, 1}, {1, 0.3, 1}, {0.2, -1, 0}, {0.2, 1, 0}};
  const Vec3 end[4] = {{-1, 0.3, -1}, {1, 0.3, -1}, {0.2, -1, 0}, {0.2, 1, 0}};
  const auto impact = edge_edge_impact(start, end, kEta);
  ASSERT_TRUE(impact);
  EXPECT_NEAR(impact->time, 0.5, 1e-12);
  EXPECT_NEAR(impact->weights[0], 0.4, 1e-9);
  EXPECT_NEAR(impact->weights[1], 0.6, 1e-9);
  EXPECT_NEAR(impact->weights[2], -0.35, 1e-9);
  EXPECT_NEAR(impact->weights[3], -0.65, 1e-9);
  EXPECT_TRUE(impact->normal.isApprox(Vec3(0, 0, 1)));
  // Shifted beyond the end of the second edge: no contact.
  const Vec3 start2[4] = {{-1, 1.3, 1}, {1, 1.3, 1}, {0.2, -1, 0}, {0.2, 1, 0}};
  const Vec3 end2[4] = {{-1, 1.3, -1}, {1, 1.3, -1}, {0.2, -1, 0}, {0.2, 1, 0}};
  EXPECT_FALSE(edge_edge_impact(start2, end2, kEta));
}

TEST(Ccd, CubicCandidatesIncludeEveryRoot) {
  // (t - 0.2)(t - 0.5)(t - 0.9): three sign changes.
  const double c[4] = {-0.09, 0.73, -1.6, 1.0};
  double times[5];
  const int n = cubic_candidate_times(c, times);
  std::vector<double> roots;
  for (int k = 0; k < n; ++k) {
    const double t = times[k];
    if (std::fabs(((c[3] * t + c[2]) * t + c[1]) * t + c[0]) < 1e-12) roots.push_back(t);
  }
  ASSERT_EQ(roots.size(), 3u);
  EXPECT_NEAR(roots[0], 0.2, 1e-12);
  EXPECT_NEAR(roots[1], 0.5, 1e-12);
  EXPECT_NEAR(roots[2], 0.9, 1e-12);
}

// Random moving vertex-triangle pairs: whenever dense sampling of the step sees the vertex
// pass through the triangle's interior, CCD reports a contact no later than that.
TEST(Ccd, RandomTrajectoriesAgreeWithSampling) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  auto rnd = [&] { return Vec3(u(rng), u(rng), u(rng)); };
  int crossings = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    Vec3 start[4], end[4];
    for (int k = 0; k < 4; ++k) {
      start[k] = rnd();
      end[k] = start[k] + 0.8 * rnd();
    }
    // Sampled first crossing of the plane with the crossing point inside the triangle
    // (by a margin, so rounding of the sampling cannot decide it).
    constexpr int kSamples = 2000;
    double sampled_time = -1;
    double previous_side = 0;
    for (int s = 0; s <= kSamples && sampled_time < 0; ++s) {
      const double t = double(s) / kSamples;
      Vec3 x[4];
      for (int k = 0; k < 4; ++k) x[k] = start[k] + t * (end[k] - start[k]);
      const Vec3 n = (x[2] - x[1]).cross(x[3] - x[1]).normalized();
      const double side = n.dot(x[0] - x[1]);
      if (s > 0 && side * previous_side < 0) {
        const TrianglePoint q = closest_on_triangle(x[0], x[1], x[2], x[3]);
        if (q.feature == TriangleFeature::Face && q.weights.minCoeff() > 0.05) sampled_time = t;
      }
      previous_side = side;
    }
    const auto impact = vertex_triangle_impact(start, end, 1e-9);
    if (sampled_time >= 0) {
      ++crossings;
      ASSERT_TRUE(impact) << "trial " << trial;
      EXPECT_LE(impact->time, sampled_time + 1e-12) << "trial " << trial;
    }
    if (impact) {
      Vec3 gap = Vec3::Zero();
      for (int k = 0; k < 4; ++k) {
        gap += impact->weights[k] * (start[k] + impact->time * (end[k] - start[k]));
      }
      EXPECT_LT(gap.norm(), 1e-9);
    }
  }
  EXPECT_GT(crossings, 50);  // the trial set does exercise crossings
}

}  // namespace
}  // namespace tissu
