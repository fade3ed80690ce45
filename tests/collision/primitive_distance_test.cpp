// Closest points of point-triangle and segment-segment pairs against dense sampling.
#include <gtest/gtest.h>

#include <random>

#include "collision/primitive_distance.h"

namespace tissu {
namespace {

Vec3 random_point(std::mt19937& rng, double scale) {
  std::uniform_real_distribution<double> u(-scale, scale);
  return Vec3(u(rng), u(rng), u(rng));
}

// Smallest distance from p to points sampled on the triangle (barycentric grid).
double sampled_triangle_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  constexpr int n = 200;
  double best = INFINITY;
  for (int i = 0; i <= n; ++i) {
    for (int j = 0; i + j <= n; ++j) {
      const double u = double(i) / n, v = double(j) / n;
      best = std::min(best, (p - (a + u * (b - a) + v * (c - a))).norm());
    }
  }
  return best;
}

TEST(PrimitiveDistance, PointTriangleMatchesSampling) {
  std::mt19937 rng(3);
  for (int trial = 0; trial < 200; ++trial) {
    const Vec3 a = random_point(rng, 1), b = random_point(rng, 1), c = random_point(rng, 1);
    const Vec3 p = random_point(rng, 2);
    const TrianglePoint q = closest_on_triangle(p, a, b, c);
    const double d = (p - q.point).norm();
    const double sampled = sampled_triangle_distance(p, a, b, c);
    // The sampling grid is 1/200 of the edges: it is at most that far from the truth.
    EXPECT_LE(d, sampled + 1e-12);
    EXPECT_GE(d, sampled - 0.02);
    EXPECT_NEAR(q.weights.sum(), 1.0, 1e-12);
    EXPECT_TRUE((q.weights[0] * a + q.weights[1] * b + q.weights[2] * c).isApprox(q.point, 1e-9));
    EXPECT_GE(q.weights.minCoeff(), -1e-12);
  }
}

TEST(PrimitiveDistance, PointTriangleFeatures) {
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  EXPECT_EQ(closest_on_triangle(Vec3(0.2, 0.2, 1), a, b, c).feature, TriangleFeature::Face);
  EXPECT_EQ(closest_on_triangle(Vec3(-1, -1, 0), a, b, c).feature, TriangleFeature::VertexA);
  EXPECT_EQ(closest_on_triangle(Vec3(2, -0.5, 0), a, b, c).feature, TriangleFeature::VertexB);
  EXPECT_EQ(closest_on_triangle(Vec3(0.5, -1, 0), a, b, c).feature, TriangleFeature::EdgeAB);
  EXPECT_EQ(closest_on_triangle(Vec3(1, 1, 0), a, b, c).feature, TriangleFeature::EdgeBC);
  EXPECT_EQ(closest_on_triangle(Vec3(-1, 0.5, 3), a, b, c).feature, TriangleFeature::EdgeCA);
  // Collinear corners: the segment they span.
  const TrianglePoint q = closest_on_triangle(Vec3(0.5, 1, 0), a, b, Vec3(2, 0, 0));
  EXPECT_TRUE(q.point.isApprox(Vec3(0.5, 0, 0)));
}

TEST(PrimitiveDistance, SegmentsMatchSampling) {
  std::mt19937 rng(5);
  for (int trial = 0; trial < 300; ++trial) {
    const Vec3 p0 = random_point(rng, 1), p1 = random_point(rng, 1);
    Vec3 q0 = random_point(rng, 1), q1 = random_point(rng, 1);
    if (trial % 10 == 0) q1 = q0 + 0.7 * (p1 - p0);  // parallel
    if (trial % 17 == 0) q1 = q0;                      // degenerate
    const SegmentPoints sp = closest_between_segments(p0, p1, q0, q1);
    double sampled = INFINITY;
    for (int i = 0; i <= 400; ++i) {
      for (int j = 0; j <= 400; ++j) {
        sampled = std::min(sampled, ((p0 + (i / 400.0) * (p1 - p0)) - (q0 + (j / 400.0) * (q1 - q0))).norm());
      }
    }
    const double d = std::sqrt(sp.distance2);
    EXPECT_LE(d, sampled + 1e-12);
    EXPECT_GE(d, sampled - 0.01);
    EXPECT_GE(sp.s, 0.0);
    EXPECT_LE(sp.s, 1.0);
    EXPECT_GE(sp.t, 0.0);
    EXPECT_LE(sp.t, 1.0);
  }
}

}  // namespace
}  // namespace tissu
