#include "collision/ccd.h"

#include <algorithm>
#include <cmath>

#include "collision/primitive_distance.h"

namespace tissu {

namespace {

double cubic_at(const double c[4], double t) { return ((c[3] * t + c[2]) * t + c[1]) * t + c[0]; }

// A root of the cubic in [lo, hi] where it changes sign, by bisection to double precision.
double bisect(const double c[4], double lo, double hi) {
  double flo = cubic_at(c, lo);
  for (int it = 0; it < 60 && hi - lo > 1e-15; ++it) {
    const double mid = 0.5 * (lo + hi);
    const double fmid = cubic_at(c, mid);
    if ((fmid <= 0.0) == (flo <= 0.0) && fmid != 0.0) {
      lo = mid;
      flo = fmid;
    } else {
      hi = mid;
    }
  }
  return 0.5 * (lo + hi);
}

Vec3 lerp(const Vec3& a, const Vec3& b, double t) { return a + t * (b - a); }

// Orients n so that it points along `gap` at the start (or against the approach when the
// gap is zero there) and returns it.
Vec3 oriented(Vec3 n, const Vec3& gap_at_start, const Vec3& gap_change) {
  const double side = n.dot(gap_at_start);
  if (side < 0.0 || (side == 0.0 && n.dot(gap_change) > 0.0)) n = -n;
  return n;
}

template <class Test>
std::optional<Impact> first_impact(const Vec3 start[4], const Vec3 end[4], Test&& test) {
  double c[4];
  coplanarity_cubic(start, end, c);
  // Points that stay coplanar throughout (or nearly): sample the step instead.
  const double scale = (start[1] - start[0]).norm() + (start[2] - start[0]).norm() +
                       (start[3] - start[0]).norm() + (end[1] - end[0]).norm() +
                       (end[2] - end[0]).norm() + (end[3] - end[0]).norm();
  const double tiny = 1e-14 * scale * scale * scale;
  double times[9];
  int n = 0;
  if (std::fabs(c[0]) + std::fabs(c[1]) + std::fabs(c[2]) + std::fabs(c[3]) <= tiny) {
    for (int k = 0; k <= 8; ++k) times[n++] = k / 8.0;
  } else {
    n = cubic_candidate_times(c, times);
  }
  for (int k = 0; k < n; ++k) {
    if (auto impact = test(times[k])) return impact;
  }
  return std::nullopt;
}

}  // namespace

void coplanarity_cubic(const Vec3 start[4], const Vec3 end[4], double c[4]) {
  const Vec3 e1 = start[1] - start[0], e2 = start[2] - start[0], q = start[3] - start[0];
  const Vec3 f1 = (end[1] - end[0]) - e1, f2 = (end[2] - end[0]) - e2, g = (end[3] - end[0]) - q;
  const Vec3 n0 = e1.cross(e2);
  const Vec3 n1 = e1.cross(f2) + f1.cross(e2);
  const Vec3 n2 = f1.cross(f2);
  c[0] = n0.dot(q);
  c[1] = n0.dot(g) + n1.dot(q);
  c[2] = n1.dot(g) + n2.dot(q);
  c[3] = n2.dot(g);
}

int cubic_candidate_times(const double c[4], double times[5]) {
  // Split [0, 1] at the derivative's roots 3 c3 t^2 + 2 c2 t + c1 = 0.
  double cuts[4] = {0.0, 0.0, 0.0, 0.0};
  int ncuts = 0;
  cuts[ncuts++] = 0.0;
  const double a = 3.0 * c[3], b = 2.0 * c[2], cc = c[1];
  double extrema[2];
  int nextrema = 0;
  if (a != 0.0) {
    const double disc = b * b - 4.0 * a * cc;
    if (disc >= 0.0) {
      const double s = std::sqrt(disc);
      // Numerically stable pair of roots.
      const double qq = -0.5 * (b + (b >= 0.0 ? s : -s));
      if (qq != 0.0) {
        extrema[nextrema++] = qq / a;
        extrema[nextrema++] = cc / qq;
      } else {
        extrema[nextrema++] = 0.0;
      }
    }
  } else if (b != 0.0) {
    extrema[nextrema++] = -cc / b;
  }
  std::sort(extrema, extrema + nextrema);
  for (int k = 0; k < nextrema; ++k) {
    if (extrema[k] > 0.0 && extrema[k] < 1.0) cuts[ncuts++] = extrema[k];
  }
  cuts[ncuts++] = 1.0;

  int n = 0;
  auto add = [&](double t) {
    if (n == 0 || t > times[n - 1]) times[n++] = t;
  };
  if (cubic_at(c, 0.0) == 0.0) add(0.0);
  for (int k = 0; k + 1 < ncuts; ++k) {
    const double lo = cuts[k], hi = cuts[k + 1];
    const double flo = cubic_at(c, lo), fhi = cubic_at(c, hi);
    if (k > 0) add(lo);  // a local extremum: the cubic may touch zero there
    if ((flo < 0.0 && fhi >= 0.0) || (flo > 0.0 && fhi <= 0.0)) add(bisect(c, lo, hi));
  }
  return n;
}

std::optional<Impact> vertex_triangle_impact(const Vec3 start[4], const Vec3 end[4], double eta) {
  // The cubic is written for ((x1 - x0) x (x2 - x0)) . (x3 - x0): put the vertex last.
  const Vec3 s[4] = {start[1], start[2], start[3], start[0]};
  const Vec3 e[4] = {end[1], end[2], end[3], end[0]};
  return first_impact(s, e, [&](double t) -> std::optional<Impact> {
    const Vec3 p = lerp(start[0], end[0], t), a = lerp(start[1], end[1], t),
               b = lerp(start[2], end[2], t), c = lerp(start[3], end[3], t);
    const TrianglePoint q = closest_on_triangle(p, a, b, c);
    if ((p - q.point).squaredNorm() > eta * eta) return std::nullopt;
    Impact impact;
    impact.time = t;
    impact.weights[0] = 1.0;
    for (int k = 0; k < 3; ++k) impact.weights[k + 1] = -q.weights[k];
    Vec3 n = (b - a).cross(c - a);
    if (n.squaredNorm() == 0.0) n = p - q.point;
    if (n.squaredNorm() == 0.0) n = Vec3::UnitZ();
    const Vec3 gap0 = start[0] - (q.weights[0] * start[1] + q.weights[1] * start[2] +
                                  q.weights[2] * start[3]);
    const Vec3 gap1 = end[0] - (q.weights[0] * end[1] + q.weights[1] * end[2] +
                                q.weights[2] * end[3]);
    impact.normal = oriented(n.normalized(), gap0, gap1 - gap0);
    return impact;
  });
}

std::optional<Impact> edge_edge_impact(const Vec3 start[4], const Vec3 end[4], double eta) {
  return first_impact(start, end, [&](double t) -> std::optional<Impact> {
    const Vec3 p0 = lerp(start[0], end[0], t), p1 = lerp(start[1], end[1], t),
               q0 = lerp(start[2], end[2], t), q1 = lerp(start[3], end[3], t);
    const SegmentPoints sp = closest_between_segments(p0, p1, q0, q1);
    if (sp.distance2 > eta * eta) return std::nullopt;
    Impact impact;
    impact.time = t;
    impact.weights[0] = 1.0 - sp.s;
    impact.weights[1] = sp.s;
    impact.weights[2] = -(1.0 - sp.t);
    impact.weights[3] = -sp.t;
    Vec3 n = (p1 - p0).cross(q1 - q0);
    if (n.squaredNorm() <= 1e-20 * (p1 - p0).squaredNorm() * (q1 - q0).squaredNorm()) {
      // Parallel edges: the direction between them at the start.
      n = (start[0] + sp.s * (start[1] - start[0])) - (start[2] + sp.t * (start[3] - start[2]));
    }
    if (n.squaredNorm() == 0.0) n = Vec3::UnitZ();
    Vec3 gap0 = Vec3::Zero(), gap1 = Vec3::Zero();
    for (int k = 0; k < 4; ++k) {
      gap0 += impact.weights[k] * start[k];
      gap1 += impact.weights[k] * end[k];
    }
    impact.normal = oriented(n.normalized(), gap0, gap1 - gap0);
    return impact;
  });
}

}  // namespace tissu
