// Vectorised membrane kernel; see membrane_simd.h. Compiled once per instruction set by
// Highway's foreach_target (this file includes itself), with -ffp-contract=off so that
// no target fuses a multiply and an add the scalar kernel keeps apart.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "physics/membrane_simd.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include <algorithm>
#include <stdexcept>

#include "physics/membrane_simd.h"

#ifndef TISSU_MEMBRANE_SIMD_ARGS
#define TISSU_MEMBRANE_SIMD_ARGS
namespace tissu {
struct MembraneKernelArgs {
  const MembraneLayout* layout;
  const double* x;  // positions, m, 3 per vertex
  const double* v;  // velocities, m/s, or null when undamped
  double e00, e01, e02, e11, e12, e22;  // stiffness E, N/m
  double tau;                           // strain-rate damping time, s
  int first, end;                       // triangles
  double* out;   // forces, N, of vertex i at out[3 i - out_offset]
  int out_offset;
};
}  // namespace tissu
#endif

HWY_BEFORE_NAMESPACE();
namespace tissu {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// The scalar kernel (membrane.cpp, accumulate_forces) lane by lane: every sum is
// evaluated in the same order, so each lane gives the scalar kernel's bits.
template <bool kDamped>
void Accumulate(const MembraneKernelArgs& k) {
  using D = hn::ScalableTag<double>;
  const D d;
  const hn::Rebind<int64_t, D> di;
  const hn::Rebind<int32_t, D> d32;
  const size_t N = hn::Lanes(d);
  constexpr size_t kMaxLanes = HWY_MAX_BYTES / sizeof(double);
  HWY_ALIGN double f[9 * kMaxLanes];  // corner forces: f[(3 j + coordinate) N + lane]

  const MembraneLayout& L = *k.layout;
  const auto e00 = hn::Set(d, k.e00), e01 = hn::Set(d, k.e01), e02 = hn::Set(d, k.e02);
  const auto e11 = hn::Set(d, k.e11), e12 = hn::Set(d, k.e12), e22 = hn::Set(d, k.e22);
  const auto tau = hn::Set(d, k.tau);
  const auto half = hn::Set(d, 0.5), one = hn::Set(d, 1.0);
  const double* px = k.x;
  const double* pv = k.v;

  for (int t = k.first; t < k.end; t += static_cast<int>(N)) {
    const auto ia = hn::PromoteTo(di, hn::LoadU(d32, L.a.data() + t));
    const auto ib = hn::PromoteTo(di, hn::LoadU(d32, L.b.data() + t));
    const auto ic = hn::PromoteTo(di, hn::LoadU(d32, L.c.data() + t));
    const auto ru0 = hn::LoadU(d, L.ru0.data() + t), ru1 = hn::LoadU(d, L.ru1.data() + t),
               ru2 = hn::LoadU(d, L.ru2.data() + t);
    const auto rv0 = hn::LoadU(d, L.rv0.data() + t), rv1 = hn::LoadU(d, L.rv1.data() + t),
               rv2 = hn::LoadU(d, L.rv2.data() + t);
    // U = sum_j r_uj p_j and V = sum_j r_vj p_j of the corners' values p (positions or
    // velocities, 3 per vertex).
    auto tangents = [&](const double* p, hn::Vec<D>* U, hn::Vec<D>* V) {
      for (int c = 0; c < 3; ++c) {
        const auto pa = hn::GatherIndex(d, p + c, ia);
        const auto pb = hn::GatherIndex(d, p + c, ib);
        const auto pc = hn::GatherIndex(d, p + c, ic);
        U[c] = hn::Add(hn::Add(hn::Mul(ru0, pa), hn::Mul(ru1, pb)), hn::Mul(ru2, pc));
        V[c] = hn::Add(hn::Add(hn::Mul(rv0, pa), hn::Mul(rv1, pb)), hn::Mul(rv2, pc));
      }
    };
    hn::Vec<D> U[3], V[3];
    tangents(px, U, V);
    auto dot = [](const hn::Vec<D>* p, const hn::Vec<D>* q) {
      return hn::Add(hn::Add(hn::Mul(p[0], q[0]), hn::Mul(p[1], q[1])), hn::Mul(p[2], q[2]));
    };
    auto euu = hn::Mul(half, hn::Sub(dot(U, U), one));
    auto evv = hn::Mul(half, hn::Sub(dot(V, V), one));
    auto euv = dot(U, V);
    if constexpr (kDamped) {
      hn::Vec<D> Ud[3], Vd[3];
      tangents(pv, Ud, Vd);
      euu = hn::Add(euu, hn::Mul(tau, dot(U, Ud)));
      evv = hn::Add(evv, hn::Mul(tau, dot(V, Vd)));
      const auto cross = hn::Add(hn::Add(hn::Add(dot(U, Vd), hn::Mul(Ud[0], V[0])),
                                         hn::Mul(Ud[1], V[1])),
                                 hn::Mul(Ud[2], V[2]));
      euv = hn::Add(euv, hn::Mul(tau, cross));
    }
    const auto neg_area = hn::Neg(hn::LoadU(d, L.area.data() + t));
    auto stress = [&](const hn::Vec<D>& ea, const hn::Vec<D>& eb, const hn::Vec<D>& ec) {
      return hn::Mul(neg_area,
                     hn::Add(hn::Add(hn::Mul(ea, euu), hn::Mul(eb, evv)), hn::Mul(ec, euv)));
    };
    const auto suu = stress(e00, e01, e02);
    const auto svv = stress(e01, e11, e12);
    const auto suv = stress(e02, e12, e22);
    const hn::Vec<D> ru[3] = {ru0, ru1, ru2}, rv[3] = {rv0, rv1, rv2};
    for (int j = 0; j < 3; ++j) {
      const auto alpha = hn::Add(hn::Mul(suu, ru[j]), hn::Mul(suv, rv[j]));
      const auto beta = hn::Add(hn::Mul(svv, rv[j]), hn::Mul(suv, ru[j]));
      for (int c = 0; c < 3; ++c) {
        hn::Store(hn::Add(hn::Mul(alpha, U[c]), hn::Mul(beta, V[c])), d, f + (3 * j + c) * N);
      }
    }
    // Scatter triangle by triangle, corners a, b, c: the scalar kernel's order of sums.
    const int count = std::min(static_cast<int>(N), k.end - t);
    for (int l = 0; l < count; ++l) {
      const int corner[3] = {L.a[t + l] - k.out_offset, L.b[t + l] - k.out_offset,
                             L.c[t + l] - k.out_offset};
      for (int j = 0; j < 3; ++j) {
        double* o = k.out + corner[j];
        o[0] += f[(3 * j + 0) * N + l];
        o[1] += f[(3 * j + 1) * N + l];
        o[2] += f[(3 * j + 2) * N + l];
      }
    }
  }
}

void MembraneForces(const MembraneKernelArgs& k) {
  if (k.v != nullptr) {
    Accumulate<true>(k);
  } else {
    Accumulate<false>(k);
  }
}

size_t KernelLanes() { return hn::Lanes(hn::ScalableTag<double>()); }

const char* KernelTarget() { return hwy::TargetName(HWY_TARGET); }

}  // namespace HWY_NAMESPACE
}  // namespace tissu
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace tissu {

HWY_EXPORT(MembraneForces);
HWY_EXPORT(KernelLanes);
HWY_EXPORT(KernelTarget);

void add_membrane_forces_simd(const Model& model, const MembraneLayout& layout,
                              const Vec3List& x, const Vec3List* v, int first, int end,
                              VertexForces out) {
  if (layout.mesh_id != model.mesh_id || layout.num_triangles != model.num_triangles()) {
    throw std::logic_error("membrane layout built for another mesh");
  }
  if (first >= end) return;
  if (HWY_DYNAMIC_DISPATCH(KernelLanes)() > static_cast<size_t>(MembraneLayout::kPadding)) {
    throw std::logic_error("membrane kernel: vectors wider than the layout's padding");
  }
  const Mat3 E = model.material.stiffness();
  const bool damped = model.material.damping > 0.0 && v != nullptr;
  MembraneKernelArgs k;
  k.layout = &layout;
  k.x = x[0].data();
  k.v = damped ? (*v)[0].data() : nullptr;
  k.e00 = E(0, 0);
  k.e01 = E(0, 1);
  k.e02 = E(0, 2);
  k.e11 = E(1, 1);
  k.e12 = E(1, 2);
  k.e22 = E(2, 2);
  k.tau = model.material.damping;
  k.first = first;
  k.end = end;
  k.out = out.data[0].data();
  k.out_offset = 3 * out.first_vertex;
  HWY_DYNAMIC_DISPATCH(MembraneForces)(k);
}

const char* membrane_simd_target() { return HWY_DYNAMIC_DISPATCH(KernelTarget)(); }

}  // namespace tissu
#endif  // HWY_ONCE
