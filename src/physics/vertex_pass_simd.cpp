// The per-vertex pass of an explicit step; see vertex_pass_simd.h. Compiled
// once per instruction set by Highway's foreach_target (this file includes
// itself), with -ffp-contract=off as membrane_simd.cpp.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "physics/vertex_pass_simd.cpp"
#include <hwy/foreach_target.h> // IWYU pragma: keep
#include <hwy/highway.h>

#include <algorithm>

#include "physics/air_damping.h"
#include "physics/gravity.h"
#include "physics/vertex_pass.h"
#include "physics/vertex_pass_simd.h"

#ifndef TISSU_VERTEX_PASS_SIMD_ARGS
#define TISSU_VERTEX_PASS_SIMD_ARGS
namespace tissu {
struct VertexPassArgs {
  const ForcePlan *plan;
  int block;
  const double
      *bending; // forces of stage 1, N, 3 per vertex, or null without bending
  const double *mass;        // kg (V)
  const double *inv_mass;    // 1/kg (V)
  const double *lumped_area; // m^2 (V)
  bool gravity;
  double g[3]; // m/s^2
  bool air_damping;
  double c; // N*s/m^3
  Integrator integrator;
  double h;           // s
  double *x;          // m, 3 per vertex
  double *v;          // m/s, 3 per vertex
  BlockCheck *check;  // or null
  const Model *model; // for the scalar stages of the tail
  Vec3List *f;
  Vec3List *xs;
  Vec3List *vs;
};
} // namespace tissu
#endif

HWY_BEFORE_NAMESPACE();
namespace tissu {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// The divergence check (check_vertex) N vertices at a time: per lane the largest squared
// speed and the first vertex that has it, merged into the block's findings at the end, so
// the findings are check_vertex's in vertex order.
class LaneCheck {
 public:
  using D = hn::ScalableTag<double>;
  explicit LaneCheck(BlockCheck *check)
      : check_(check), checking_(check != nullptr && check->first_bad < 0) {}

  // Vertices i .. i + N - 1 with positions x0, x1, x2 (m) and velocities v0, v1, v2
  // (m/s) of xs and vs: a non-finite one ends the lanes' work and the group is checked
  // vertex by vertex, as is every vertex after it.
  void Group(int i, hn::Vec<D> x0, hn::Vec<D> x1, hn::Vec<D> x2, hn::Vec<D> v0,
             hn::Vec<D> v1, hn::Vec<D> v2, const Vec3List &xs, const Vec3List &vs) {
    if (!checking_)
      return;
    const D d;
    const auto finite = hn::And(
        hn::And(hn::And(hn::IsFinite(x0), hn::IsFinite(x1)), hn::IsFinite(x2)),
        hn::And(hn::And(hn::IsFinite(v0), hn::IsFinite(v1)), hn::IsFinite(v2)));
    if (HWY_LIKELY(hn::AllTrue(d, finite))) {
      const auto s2 =
          hn::Add(hn::Add(hn::Mul(v0, v0), hn::Mul(v1, v1)), hn::Mul(v2, v2));
      const auto faster = hn::Gt(s2, best_);
      best_ = hn::IfThenElse(faster, s2, best_);
      best_index_ = hn::IfThenElse(faster, hn::Iota(d, static_cast<double>(i)),
                                   best_index_);
      return;
    }
    Merge();
    for (int l = 0; l < static_cast<int>(hn::Lanes(d)); ++l)
      check_vertex(i + l, xs[i + l], vs[i + l], *check_);
    checking_ = false;
  }

  // The lanes' findings: the largest speed, at the first vertex that has it.
  void Merge() {
    if (!checking_)
      return;
    const D d;
    constexpr size_t kMaxLanes = HWY_MAX_BYTES / sizeof(double);
    HWY_ALIGN double top[kMaxLanes], index[kMaxLanes];
    hn::Store(best_, d, top);
    hn::Store(best_index_, d, index);
    for (size_t l = 0; l < hn::Lanes(d); ++l) {
      if (index[l] < 0)
        continue;
      const bool first_of_top =
          top[l] == check_->top_speed2 && index[l] < check_->fastest;
      if (top[l] > check_->top_speed2 || first_of_top) {
        check_->top_speed2 = top[l];
        check_->fastest = static_cast<int>(index[l]);
      }
    }
  }

 private:
  BlockCheck *check_;
  bool checking_;
  hn::Vec<D> best_ = hn::Zero(D());          // m^2/s^2
  hn::Vec<D> best_index_ = hn::Set(D(), -1.0);
};

void FinishBlock(const VertexPassArgs &k) {
  using D = hn::ScalableTag<double>;
  const D d;
  const int N = static_cast<int>(hn::Lanes(d));
  const ForcePlan &plan = *k.plan;
  const int first = plan.block_begin(k.block), end = plan.block_end(k.block);
  const int n3 = 3 * (end - first);
  HWY_ALIGN double
      f[3 * ForcePlan::kVerticesPerBlock]; // forces of the block, N

  // Bending (or zero), then the chunk buffers in chunk order: elementwise sums.
  if (k.bending != nullptr) {
    std::copy(k.bending + 3 * first, k.bending + 3 * end, f);
  } else {
    std::fill(f, f + n3, 0.0);
  }
  for (int e = plan.block_chunk_start[k.block];
       e < plan.block_chunk_start[k.block + 1]; ++e) {
    const ForcePlan::Chunk &c = plan.chunks[plan.block_chunks[e]];
    const int lo = std::max(first, c.first_vertex),
              hi = std::min(end, c.end_vertex);
    const double *p = plan.partial[c.offset + (lo - c.first_vertex)].data();
    double *q = f + 3 * (lo - first);
    const int count = 3 * (hi - lo);
    int j = 0;
    for (; j + N <= count; j += N) {
      hn::StoreU(hn::Add(hn::LoadU(d, q + j), hn::LoadU(d, p + j)), d, q + j);
    }
    for (; j < count; ++j)
      q[j] += p[j];
  }

  // Gravity, air damping and the integrator, N vertices at a time.
  const auto h = hn::Set(d, k.h), two = hn::Set(d, 2.0), cd = hn::Set(d, k.c);
  const auto gx = hn::Set(d, k.g[0]), gy = hn::Set(d, k.g[1]),
             gz = hn::Set(d, k.g[2]);
  LaneCheck check(k.check);
  const bool symplectic = k.integrator != Integrator::ExplicitEuler;
  int i = first;
  for (; i + N <= end; i += N) {
    double *fi = f + 3 * (i - first);
    double *xi = k.x + 3 * i;
    double *vi = k.v + 3 * i;
    hn::Vec<D> fx, fy, fz, x0, x1, x2, v0, v1, v2;
    hn::LoadInterleaved3(d, fi, fx, fy, fz);
    hn::LoadInterleaved3(d, xi, x0, x1, x2);
    hn::LoadInterleaved3(d, vi, v0, v1, v2);
    if (k.gravity) {
      const auto m = hn::LoadU(d, k.mass + i);
      fx = hn::Add(fx, hn::Mul(m, gx));
      fy = hn::Add(fy, hn::Mul(m, gy));
      fz = hn::Add(fz, hn::Mul(m, gz));
    }
    if (k.air_damping) {
      const auto s = hn::Mul(cd, hn::LoadU(d, k.lumped_area + i));
      fx = hn::Sub(fx, hn::Mul(s, v0));
      fy = hn::Sub(fy, hn::Mul(s, v1));
      fz = hn::Sub(fz, hn::Mul(s, v2));
    }
    auto w = hn::Mul(h, hn::LoadU(d, k.inv_mass + i));
    if (k.integrator == Integrator::BenameurDjedi)
      w = hn::Div(w, two);
    const auto advance_x = [&] {
      x0 = hn::Add(x0, hn::Mul(h, v0));
      x1 = hn::Add(x1, hn::Mul(h, v1));
      x2 = hn::Add(x2, hn::Mul(h, v2));
    };
    const auto advance_v = [&] {
      v0 = hn::Add(v0, hn::Mul(w, fx));
      v1 = hn::Add(v1, hn::Mul(w, fy));
      v2 = hn::Add(v2, hn::Mul(w, fz));
    };
    if (symplectic) { // eq. 10 and the paper's scheme: the new velocity moves
                      // the vertex
      advance_v();
      advance_x();
    } else { // eq. 9: the old one
      advance_x();
      advance_v();
    }
    hn::StoreInterleaved3(x0, x1, x2, d, xi);
    hn::StoreInterleaved3(v0, v1, v2, d, vi);
    check.Group(i, x0, x1, x2, v0, v1, v2, *k.xs, *k.vs);
  }
  check.Merge();
  // The tail (fewer than N vertices, last block only): the scalar stages.
  if (i == end)
    return;
  std::copy(f + 3 * (i - first), f + n3, (*k.f)[i].data());
  const VertexForces out = VertexForces::of(*k.f);
  if (k.gravity)
    add_gravity(*k.model, *k.model->gravity, i, end, out);
  if (k.air_damping)
    add_air_damping(*k.model, k.c, *k.vs, i, end, out);
  integrate_vertices(*k.model, i, end, *k.f, *k.xs, *k.vs);
  if (k.check == nullptr)
    return;
  for (; i < end; ++i)
    check_vertex(i, (*k.xs)[i], (*k.vs)[i], *k.check);
}

void CheckBlock(const Vec3List &xs, const Vec3List &vs, int first, int end,
                BlockCheck *check_out) {
  using D = hn::ScalableTag<double>;
  const D d;
  const int N = static_cast<int>(hn::Lanes(d));
  LaneCheck check(check_out);
  int i = first;
  for (; i + N <= end; i += N) {
    hn::Vec<D> x0, x1, x2, v0, v1, v2;
    hn::LoadInterleaved3(d, xs[i].data(), x0, x1, x2);
    hn::LoadInterleaved3(d, vs[i].data(), v0, v1, v2);
    check.Group(i, x0, x1, x2, v0, v1, v2, xs, vs);
  }
  check.Merge();
  for (; i < end; ++i)
    check_vertex(i, xs[i], vs[i], *check_out);
}

} // namespace HWY_NAMESPACE
} // namespace tissu
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace tissu {

HWY_EXPORT(FinishBlock);
HWY_EXPORT(CheckBlock);

void check_block_simd(const Vec3List &x, const Vec3List &v, int first, int end,
                      BlockCheck &check) {
  HWY_DYNAMIC_DISPATCH(CheckBlock)(x, v, first, end, &check);
}

void finish_block_simd(const Model &model, const ForcePlan &plan, int block,
                       Vec3List &f, Vec3List &x, Vec3List &v,
                       BlockCheck *check) {
  VertexPassArgs k;
  k.plan = &plan;
  k.block = block;
  k.bending = model.bending ? f[0].data() : nullptr;
  k.mass = model.mass.data();
  k.inv_mass = model.inv_mass.data();
  k.lumped_area = model.lumped_area.data();
  k.gravity = model.gravity.has_value();
  for (int c = 0; c < 3; ++c)
    k.g[c] = k.gravity ? (*model.gravity)[c] : 0.0;
  k.air_damping = model.air_damping.has_value();
  k.c = model.air_damping.value_or(0.0);
  k.integrator = model.integrator;
  k.h = model.dt;
  k.x = x[0].data();
  k.v = v[0].data();
  k.check = check;
  k.model = &model;
  k.f = &f;
  k.xs = &x;
  k.vs = &v;
  HWY_DYNAMIC_DISPATCH(FinishBlock)(k);
}

} // namespace tissu
#endif // HWY_ONCE
