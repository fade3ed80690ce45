// The near-test of the collision stage; see obstacle_simd.h. Compiled once per
// instruction set by Highway's foreach_target (this file includes itself).
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "physics/obstacle_simd.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "physics/obstacle_simd.h"

#ifndef TISSU_OBSTACLE_SIMD_SHAPES
#define TISSU_OBSTACLE_SIMD_SHAPES
namespace tissu {

// A placed sphere, cylinder or plane as the kernel reads it.
struct NearShape {
  ObstacleKind kind;
  double center[3];     // m: placed centre or plane point
  double axis[3];       // cylinder axis or plane normal (unit)
  double thickness;     // m
  double reach2;        // m^2: sphere, (radius + thickness)^2 widened by the slack
  double side;          // m: cylinder, radius + thickness
  double cap;           // m: cylinder, half length + thickness
  double size;          // m: radius + half length + thickness, for the slack
};

// Relative slack of the test: the two distance computations round differently by a few
// 1e-16 of the distances' scale; a vertex within 1e-12 of it counts as near.
constexpr double kNearSlack = 1e-12;

struct NearArgs {
  const NearShape* shapes;
  int count;
  const double* x;  // m, 3 per vertex
  int first, end;
  int* selected;
};

}  // namespace tissu
#endif

HWY_BEFORE_NAMESPACE();
namespace tissu {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

int SelectNear(const NearArgs& k) {
  using D = hn::ScalableTag<double>;
  const D d;
  const int N = static_cast<int>(hn::Lanes(d));
  const auto slack = hn::Set(d, kNearSlack);
  int count = 0;
  int i = k.first;
  for (; i + N <= k.end; i += N) {
    hn::Vec<D> px, py, pz;
    hn::LoadInterleaved3(d, k.x + 3 * i, px, py, pz);
    // Far from an obstacle: a lower bound of the distance at least the thickness plus the
    // slack; a NaN compares false, so a non-finite vertex stays near.
    auto far_all = hn::And(hn::And(hn::IsFinite(px), hn::IsFinite(py)), hn::IsFinite(pz));
    for (int o = 0; o < k.count; ++o) {
      const NearShape& s = k.shapes[o];
      const auto dx = hn::Sub(px, hn::Set(d, s.center[0]));
      const auto dy = hn::Sub(py, hn::Set(d, s.center[1]));
      const auto dz = hn::Sub(pz, hn::Set(d, s.center[2]));
      if (s.kind == ObstacleKind::Sphere) {
        const auto d2 = hn::Add(hn::Add(hn::Mul(dx, dx), hn::Mul(dy, dy)), hn::Mul(dz, dz));
        far_all = hn::And(far_all, hn::Ge(d2, hn::Set(d, s.reach2)));
        continue;
      }
      const auto ax = hn::Set(d, s.axis[0]), ay = hn::Set(d, s.axis[1]),
                 az = hn::Set(d, s.axis[2]);
      const auto h = hn::Add(hn::Add(hn::Mul(dx, ax), hn::Mul(dy, ay)), hn::Mul(dz, az));
      const auto scale = hn::Add(hn::Add(hn::Add(hn::Abs(dx), hn::Abs(dy)), hn::Abs(dz)),
                                 hn::Set(d, s.size));
      const auto margin = hn::Mul(slack, scale);
      if (s.kind == ObstacleKind::Plane) {
        far_all = hn::And(far_all, hn::Ge(h, hn::Add(hn::Set(d, s.thickness), margin)));
        continue;
      }
      // Cylinder: the distance is at least the larger of the side's and the caps'.
      const auto far_cap = hn::Ge(hn::Abs(h), hn::Add(hn::Set(d, s.cap), margin));
      const auto rx = hn::Sub(dx, hn::Mul(h, ax));
      const auto ry = hn::Sub(dy, hn::Mul(h, ay));
      const auto rz = hn::Sub(dz, hn::Mul(h, az));
      const auto r2 = hn::Add(hn::Add(hn::Mul(rx, rx), hn::Mul(ry, ry)), hn::Mul(rz, rz));
      const auto side = hn::Add(hn::Set(d, s.side), margin);
      far_all = hn::And(far_all, hn::Or(far_cap, hn::Ge(r2, hn::Mul(side, side))));
    }
    if (HWY_LIKELY(hn::AllTrue(d, far_all))) continue;
    uint8_t bits[8] = {};
    hn::StoreMaskBits(d, hn::Not(far_all), bits);
    for (int l = 0; l < N; ++l) {
      if ((bits[l / 8] >> (l % 8)) & 1) k.selected[count++] = i + l;
    }
  }
  // The tail (fewer than N vertices): all of them.
  for (; i < k.end; ++i) k.selected[count++] = i;
  return count;
}

}  // namespace HWY_NAMESPACE
}  // namespace tissu
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace tissu {

HWY_EXPORT(SelectNear);

int select_near_obstacles(const std::vector<PlacedObstacle>& placed, const Vec3List& x,
                          int first, int end, int* selected) {
  constexpr int kMaxShapes = 16;
  NearShape shapes[kMaxShapes];
  const bool testable = placed.size() <= kMaxShapes &&
                        std::none_of(placed.begin(), placed.end(), [](const PlacedObstacle& p) {
                          return p.obstacle->kind == ObstacleKind::Mesh;
                        });
  if (!testable) {
    for (int i = first; i < end; ++i) selected[i - first] = i;
    return end - first;
  }
  for (size_t o = 0; o < placed.size(); ++o) {
    const Obstacle& ob = *placed[o].obstacle;
    NearShape& s = shapes[o];
    s.kind = ob.kind;
    for (int c = 0; c < 3; ++c) {
      s.center[c] = placed[o].center[c];
      s.axis[c] = ob.axis[c];
    }
    const double reach = ob.radius + ob.thickness;
    s.thickness = ob.thickness;
    s.reach2 = reach * reach * (1.0 + kNearSlack);
    s.side = reach;
    s.cap = ob.half_length + ob.thickness;
    s.size = std::fabs(ob.radius) + std::fabs(ob.half_length) + std::fabs(ob.thickness);
  }
  const NearArgs k{shapes, static_cast<int>(placed.size()), x.empty() ? nullptr : x[0].data(),
                   first, end, selected};
  return HWY_DYNAMIC_DISPATCH(SelectNear)(k);
}

}  // namespace tissu
#endif  // HWY_ONCE
