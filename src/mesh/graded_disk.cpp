#include "mesh/graded_disk.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "mesh/random.h"

namespace tissu {
namespace {

constexpr double kRowHeight = 0.86602540378443865;  // sqrt(3) / 2: equilateral rows
constexpr int kSamples = 4000;                        // per segment, to invert the ring index

// Radii of the rings strictly inside (a, b] (b included), about one row apart: the row
// index s(r) = integral of dr / (row height) is cut into equal steps.
std::vector<double> ring_radii(double a, double b, const DiskGrading& g, double coarse) {
  std::vector<double> r(kSamples + 1), s(kSamples + 1, 0.0);
  for (int i = 0; i <= kSamples; ++i) r[i] = a + (b - a) * i / kSamples;
  for (int i = 1; i <= kSamples; ++i) {
    const double mid = 0.5 * (r[i - 1] + r[i]);
    s[i] = s[i - 1] + (r[i] - r[i - 1]) / (kRowHeight * graded_edge(g, coarse, mid));
  }
  const int rings = std::max(1, static_cast<int>(std::lround(s[kSamples])));
  std::vector<double> out;
  size_t i = 1;
  for (int k = 1; k < rings; ++k) {
    const double target = s[kSamples] * k / rings;
    while (s[i] < target) ++i;
    const double t = (target - s[i - 1]) / (s[i] - s[i - 1]);
    out.push_back(r[i - 1] + t * (r[i] - r[i - 1]));
  }
  out.push_back(b);
  return out;
}

// Points on the rings for the coarse edge `coarse` (m); rings keep their radius exactly.
Vec2List ring_points(double radius, double inner, const DiskGrading& g, double coarse,
                     uint64_t seed) {
  std::vector<double> radii = ring_radii(0.0, inner, g, coarse);
  for (double r : ring_radii(inner, radius, g, coarse)) radii.push_back(r);
  PortableRandom random(seed);
  Vec2List points{Vec2::Zero()};
  for (double r : radii) {
    const int count =
        std::max(3, static_cast<int>(std::lround(2.0 * kPi * r / graded_edge(g, coarse, r))));
    const double turn = random.uniform(0.0, 2.0 * kPi / count);
    for (int i = 0; i < count; ++i) {
      const double angle = turn + 2.0 * kPi * i / count;
      points.emplace_back(r * std::cos(angle), r * std::sin(angle));
    }
  }
  return points;
}

}  // namespace

double graded_edge(const DiskGrading& g, double coarse, double r) {
  double depth = 1.0;  // 1 inside the band, 0 a transition's width or more away from it
  if (r < g.inner) depth = g.transition > 0.0 ? 1.0 - (g.inner - r) / g.transition : 0.0;
  if (r > g.outer) depth = g.transition > 0.0 ? 1.0 - (r - g.outer) / g.transition : 0.0;
  depth = std::clamp(depth, 0.0, 1.0);
  return coarse * (1.0 - depth * (1.0 - g.fine_ratio));
}

Vec2List graded_disk_points(double radius, int triangles, uint64_t seed, double inner_radius,
                            const DiskGrading& grading) {
  // Equilateral triangles of edge h cover sqrt(3)/4 h^2 each: the count over the disk.
  double weighted = 0.0;  // integral of 2 pi r / (edge / coarse)^2 dr
  const int n = 4 * kSamples;
  for (int i = 0; i < n; ++i) {
    const double r = (i + 0.5) * radius / n;
    const double e = graded_edge(grading, 1.0, r);
    weighted += 2.0 * kPi * r / (e * e) * radius / n;
  }
  double coarse = std::sqrt(4.0 * weighted / (std::sqrt(3.0) * triangles));
  // Ring counts round: three corrections of the coarse edge by the count the points give
  // (a triangulation of V points with B on the hull has 2 V - B - 2 triangles).
  Vec2List points = ring_points(radius, inner_radius, grading, coarse, seed);
  for (int pass = 0; pass < 3; ++pass) {
    const double rim =
        std::max(3.0, std::round(2.0 * kPi * radius / graded_edge(grading, coarse, radius)));
    const double count = 2.0 * static_cast<double>(points.size()) - rim - 2.0;
    coarse *= std::sqrt(count / triangles);
    points = ring_points(radius, inner_radius, grading, coarse, seed);
  }
  return points;
}

}  // namespace tissu
