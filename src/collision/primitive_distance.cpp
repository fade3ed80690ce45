#include "collision/primitive_distance.h"

#include <algorithm>

namespace tissu {

namespace {

double clamp01(double x) { return std::min(1.0, std::max(0.0, x)); }

}  // namespace

TrianglePoint closest_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  // Ericson 5.1.5: find the Voronoi region of p by the signs of dot products.
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return {a, Vec3(1, 0, 0), TriangleFeature::VertexA};
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return {b, Vec3(0, 1, 0), TriangleFeature::VertexB};
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 && d1 - d3 > 0.0) {
    const double v = d1 / (d1 - d3);
    return {a + v * ab, Vec3(1 - v, v, 0), TriangleFeature::EdgeAB};
  }
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return {c, Vec3(0, 0, 1), TriangleFeature::VertexC};
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 && d2 - d6 > 0.0) {
    const double w = d2 / (d2 - d6);
    return {a + w * ac, Vec3(1 - w, 0, w), TriangleFeature::EdgeCA};
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 && (d4 - d3) + (d5 - d6) > 0.0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return {b + w * (c - b), Vec3(0, 1 - w, w), TriangleFeature::EdgeBC};
  }
  const double sum = va + vb + vc;
  if (!(sum > 0.0)) {
    // Collinear corners: the closest of the three edges.
    TrianglePoint best{a, Vec3(1, 0, 0), TriangleFeature::VertexA};
    double best_d2 = (p - a).squaredNorm();
    const Vec3* corners[3] = {&a, &b, &c};
    const TriangleFeature edges[3] = {TriangleFeature::EdgeAB, TriangleFeature::EdgeBC,
                                      TriangleFeature::EdgeCA};
    for (int e = 0; e < 3; ++e) {
      const Vec3& u = *corners[e];
      const Vec3& w = *corners[(e + 1) % 3];
      const double len2 = (w - u).squaredNorm();
      const double s = len2 > 0.0 ? clamp01((p - u).dot(w - u) / len2) : 0.0;
      const Vec3 q = u + s * (w - u);
      const double d2 = (p - q).squaredNorm();
      if (d2 < best_d2) {
        best_d2 = d2;
        Vec3 weights = Vec3::Zero();
        weights[e] = 1.0 - s;
        weights[(e + 1) % 3] = s;
        best = {q, weights, edges[e]};
      }
    }
    return best;
  }
  const double v = vb / sum, w = vc / sum;
  return {a + v * ab + w * ac, Vec3(1 - v - w, v, w), TriangleFeature::Face};
}

SegmentPoints closest_between_segments(const Vec3& p0, const Vec3& p1, const Vec3& q0,
                                       const Vec3& q1) {
  // Ericson 5.1.9, with the degenerate cases handled by clamping.
  const Vec3 d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  double s = 0.0, t = 0.0;
  if (a <= 0.0 && e <= 0.0) {
    s = t = 0.0;
  } else if (a <= 0.0) {
    s = 0.0;
    t = clamp01(f / e);
  } else {
    const double c = d1.dot(r);
    if (e <= 0.0) {
      t = 0.0;
      s = clamp01(-c / a);
    } else {
      const double b = d1.dot(d2);
      const double denom = a * e - b * b;  // >= 0; 0 when parallel
      s = denom > 1e-14 * a * e ? clamp01((b * f - c * e) / denom) : 0.0;
      t = (b * s + f) / e;
      if (t < 0.0) {
        t = 0.0;
        s = clamp01(-c / a);
      } else if (t > 1.0) {
        t = 1.0;
        s = clamp01((b - c) / a);
      }
    }
  }
  const Vec3 between = (p0 + s * d1) - (q0 + t * d2);
  return {s, t, between.squaredNorm()};
}

}  // namespace tissu
