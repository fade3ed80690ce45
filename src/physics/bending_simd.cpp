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
  const double* x;       // positions, m, 3 per vertex
  int num_vertices;
  double origin[3];  // m
  int first, end;    // vertices
  double* out;       // forces, N, of vertex i at out[3 (i - first_vertex)]
};
}  // namespace tissu
#endif

HWY_BEFORE_NAMESPACE();
namespace tissu {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

void BendingForces(const BendingKernelArgs& k) {
  using D = hn::CappedTag<double, 4>;
  if constexpr (hn::MaxLanes(D()) < 4) {
    // Fewer than 4 lanes: the scalar loop of bending.cpp.
    for (int i = k.first; i < k.end; ++i) {
      double q[3] = {0.0, 0.0, 0.0};
      for (int e = k.starts[i]; e < k.starts[i + 1]; ++e) {
        const double* p = k.x + 3 * k.columns[e];
        for (int c = 0; c < 3; ++c) q[c] += k.values[e] * (p[c] - k.origin[c]);
      }
      double* o = k.out + 3 * (i - k.first);
      for (int c = 0; c < 3; ++c) o[c] -= q[c];
    }
  } else {
    const D d;
    HWY_ALIGN const double origin4[4] = {k.origin[0], k.origin[1], k.origin[2], 0.0};
    const auto origin = hn::Load(d, origin4);
    HWY_ALIGN double last[4] = {0.0, 0.0, 0.0, 0.0};  // the last vertex, padded
    HWY_ALIGN double q[4];
    const int final_vertex = k.num_vertices - 1;
    for (int i = k.first; i < k.end; ++i) {
      auto sum = hn::Zero(d);  // lane 3 carries the next vertex's x: never used
      for (int e = k.starts[i]; e < k.starts[i + 1]; ++e) {
        const int j = k.columns[e];
        hn::Vec<D> xj;
        if (j < final_vertex) {
          xj = hn::LoadU(d, k.x + 3 * j);
        } else {
          for (int c = 0; c < 3; ++c) last[c] = k.x[3 * j + c];
          xj = hn::Load(d, last);
        }
        sum = hn::Add(hn::Mul(hn::Set(d, k.values[e]), hn::Sub(xj, origin)), sum);
      }
      hn::Store(sum, d, q);
      double* o = k.out + 3 * (i - k.first);
      o[0] -= q[0];
      o[1] -= q[1];
      o[2] -= q[2];
    }
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace tissu
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace tissu {

HWY_EXPORT(BendingForces);

void add_bending_forces_simd(const BendingModel& model, const Vec3List& x, const Vec3& origin,
                             int first, int end, VertexForces out) {
  if (first >= end) return;
  const auto& Q = model.stiffness;
  BendingKernelArgs k;
  k.starts = Q.outerIndexPtr();
  k.columns = Q.innerIndexPtr();
  k.values = Q.valuePtr();
  k.x = x[0].data();
  k.num_vertices = static_cast<int>(x.size());
  for (int c = 0; c < 3; ++c) k.origin[c] = origin[c];
  k.first = first;
  k.end = end;
  k.out = out[first].data();
  HWY_DYNAMIC_DISPATCH(BendingForces)(k);
}

}  // namespace tissu
#endif  // HWY_ONCE
