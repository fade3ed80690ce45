// Bending forces with a vertex's coordinates in one vector; see bending_simd.h. Compiled
// once per instruction set by Highway's foreach_target (this file includes itself),
// with -ffp-contract=off as membrane_simd.cpp.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "physics/bending_simd.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include "physics/bending.h"
#include "physics/bending_simd.h"

#ifndef TISSU_BENDING_SIMD_ARGS
#define TISSU_BENDING_SIMD_ARGS
namespace tissu {
struct BendingKernelArgs {
  const int* starts;     // row starts of Q (V + 1)
  const int* columns;    // column of each entry
  const double* values;  // Q_ij, N/m
  const double* xc;      // positions minus the origin, m, 4 per vertex (CenteredPoint)
  int first, end;        // vertices
  double* out;           // forces, N, of vertex i at out[3 (i - first)]
};
}  // namespace tissu
#endif

HWY_BEFORE_NAMESPACE();
namespace tissu {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

void BendingForces(const BendingKernelArgs& k) {
  using D = hn::CappedTag<double, 4>;
  const D d;
  if (hn::Lanes(d) < 4) {
    // Fewer than 4 lanes (narrow instruction sets; scalable vectors may be narrow at run
    // time): the scalar loop of bending.cpp.
    for (int i = k.first; i < k.end; ++i) {
      double q[3] = {0.0, 0.0, 0.0};
      for (int e = k.starts[i]; e < k.starts[i + 1]; ++e) {
        const double* p = k.xc + 4 * k.columns[e];
        for (int c = 0; c < 3; ++c) q[c] += k.values[e] * p[c];
      }
      double* o = k.out + 3 * (i - k.first);
      for (int c = 0; c < 3; ++c) o[c] -= q[c];
    }
  } else {
    // Q_ij xc_j; lane 3 carries the padding's zeros, never used.
    auto entry = [&](int e) {
      return hn::Mul(hn::Set(d, k.values[e]), hn::Load(d, k.xc + 4 * k.columns[e]));
    };
    HWY_ALIGN double q[4];
    auto subtract = [&](int i, const hn::Vec<D>& sum) {
      hn::Store(sum, d, q);
      double* o = k.out + 3 * (i - k.first);
      o[0] -= q[0];
      o[1] -= q[1];
      o[2] -= q[2];
    };
    // Rows two at a time: each row's sum is still one chain of additions in the scalar
    // loop's order, and the two chains overlap (a row waits on its additions' latency).
    int i = k.first;
    for (; i + 1 < k.end; i += 2) {
      int a = k.starts[i], b = k.starts[i + 1];
      const int a_end = k.starts[i + 1], b_end = k.starts[i + 2];
      auto sum_a = hn::Zero(d), sum_b = hn::Zero(d);
      for (; a < a_end && b < b_end; ++a, ++b) {
        sum_a = hn::Add(entry(a), sum_a);
        sum_b = hn::Add(entry(b), sum_b);
      }
      for (; a < a_end; ++a) sum_a = hn::Add(entry(a), sum_a);
      for (; b < b_end; ++b) sum_b = hn::Add(entry(b), sum_b);
      subtract(i, sum_a);
      subtract(i + 1, sum_b);
    }
    if (i < k.end) {
      auto sum = hn::Zero(d);
      for (int e = k.starts[i]; e < k.starts[i + 1]; ++e) sum = hn::Add(entry(e), sum);
      subtract(i, sum);
    }
  }
}

// xc_i = (x_i - origin, 0) for n vertices: one 4-double load per vertex (its x, y, z and
// the next vertex's x, set to 0), the last vertex alone.
void CenterPositions(const double* x, int n, const double* origin, double* xc) {
  using D = hn::CappedTag<double, 4>;
  const D d;
  int i = 0;
  if (hn::Lanes(d) >= 4) {
    HWY_ALIGN const double origin4[4] = {origin[0], origin[1], origin[2], 0.0};
    const auto o = hn::Load(d, origin4);
    const auto xyz = hn::FirstN(d, 3);
    for (; i + 1 < n; ++i) {
      hn::Store(hn::IfThenElseZero(xyz, hn::Sub(hn::LoadU(d, x + 3 * i), o)), d, xc + 4 * i);
    }
  }
  for (; i < n; ++i) {
    for (int c = 0; c < 3; ++c) xc[4 * i + c] = x[3 * i + c] - origin[c];
    xc[4 * i + 3] = 0.0;
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace tissu
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace tissu {

HWY_EXPORT(BendingForces);
HWY_EXPORT(CenterPositions);

void center_positions_simd(const Vec3List& x, const Vec3& origin, CenteredPositions& xc) {
  xc.resize(x.size());
  if (x.empty()) return;
  HWY_DYNAMIC_DISPATCH(CenterPositions)(x[0].data(), static_cast<int>(x.size()), origin.data(),
                                         xc.data()->c);
}

void add_bending_forces_simd(const BendingModel& model, const CenteredPositions& xc, int first,
                             int end, VertexForces out) {
  if (first >= end) return;
  const auto& Q = model.stiffness;
  BendingKernelArgs k;
  k.starts = Q.outerIndexPtr();
  k.columns = Q.innerIndexPtr();
  k.values = Q.valuePtr();
  k.xc = xc.data()->c;
  k.first = first;
  k.end = end;
  k.out = out[first].data();
  HWY_DYNAMIC_DISPATCH(BendingForces)(k);
}

}  // namespace tissu
#endif  // HWY_ONCE
