// See fxaa_edges_simd.h. Compiled once per instruction set by Highway's foreach_target
// (this file includes itself), with -ffp-contract=off (src/render/CMakeLists.txt).
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "render/image/fxaa_edges_simd.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include <algorithm>

#include "render/image/fxaa_edges_simd.h"

HWY_BEFORE_NAMESPACE();
namespace tissu {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using DF = hn::ScalableTag<float>;
using DI = hn::RebindToSigned<DF>;
using DU = hn::RebindToUnsigned<DF>;
using VF = hn::Vec<DF>;
using VI = hn::Vec<DI>;

struct RgbVec {
  VF r, g, b;
};

// Byte `kShift / 8` of each 32-bit lane, 0..255.
template <int kShift>
HWY_INLINE VI byte_at(VI word) {
  return hn::And(hn::ShiftRight<kShift>(word), hn::Set(DI(), 0xFF));
}

// One channel of a bilinear sample: the corners' words were gathered at the top-left
// corner (a, c: channel at kShift) and one byte before the right-hand corner (b, d:
// channel at kShift + 8, so that no read passes the image's last byte).
template <int kShift>
HWY_INLINE VF bilinear(VI a, VI b, VI c, VI d, VF fx, VF fy) {
  const DF df;
  const VI ia = byte_at<kShift>(a), ib = byte_at<kShift + 8>(b);
  const VI ic = byte_at<kShift>(c), id = byte_at<kShift + 8>(d);
  const VF top = hn::Add(hn::ConvertTo(df, ia), hn::Mul(hn::ConvertTo(df, hn::Sub(ib, ia)), fx));
  const VF bottom = hn::Add(hn::ConvertTo(df, ic), hn::Mul(hn::ConvertTo(df, hn::Sub(id, ic)), fx));
  return hn::Add(top, hn::Mul(hn::Sub(bottom, top), fy));
}

// Bilinear samples of the image at pixel coordinates (x, y), clamped to it.
HWY_INLINE RgbVec sample(const std::int32_t* base, int width, int height, VF x, VF y) {
  const DF df;
  const DI di;
  x = hn::Min(hn::Max(x, hn::Zero(df)), hn::Set(df, float(width - 1)));
  y = hn::Min(hn::Max(y, hn::Zero(df)), hn::Set(df, float(height - 1)));
  const VI x0 = hn::Min(hn::ConvertTo(di, x), hn::Set(di, width - 2));
  const VI y0 = hn::Min(hn::ConvertTo(di, y), hn::Set(di, height - 2));
  const VF fx = hn::Sub(x, hn::ConvertTo(df, x0)), fy = hn::Sub(y, hn::ConvertTo(df, y0));
  const VI at = hn::Mul(hn::Add(hn::Mul(y0, hn::Set(di, width)), x0), hn::Set(di, 3));
  const VI below = hn::Add(at, hn::Set(di, 3 * width));
  const VI two = hn::Set(di, 2);
  const VI a = hn::GatherOffset(di, base, at), b = hn::GatherOffset(di, base, hn::Add(at, two));
  const VI c = hn::GatherOffset(di, base, below), d = hn::GatherOffset(di, base, hn::Add(below, two));
  return {bilinear<0>(a, b, c, d, fx, fy), bilinear<8>(a, b, c, d, fx, fy),
          bilinear<16>(a, b, c, d, fx, fy)};
}

HWY_INLINE VI to_byte(VF v) {
  const DF df;
  const VF clamped = hn::Min(hn::Max(hn::Add(v, hn::Set(df, 0.5f)), hn::Zero(df)), hn::Set(df, 255.0f));
  return hn::ConvertTo(DI(), clamped);
}

// Edge pixels [i, i + Lanes) of the arrays.
HWY_INLINE void blend_lanes(const std::int32_t* base, int width, int height, const std::int32_t* xs,
                            const std::int32_t* ys, const float* dxs, const float* dys,
                            const float* los, const float* his, std::uint32_t* out) {
  const DF df;
  const DI di;
  const VF x = hn::ConvertTo(df, hn::LoadU(di, xs)), y = hn::ConvertTo(df, hn::LoadU(di, ys));
  const VF dx = hn::LoadU(df, dxs), dy = hn::LoadU(df, dys);
  const VF six = hn::Set(df, 6.0f), half = hn::Set(df, 0.5f), quarter = hn::Set(df, 0.25f);
  const RgbVec a = sample(base, width, height, hn::Sub(x, hn::Div(dx, six)), hn::Sub(y, hn::Div(dy, six)));
  const RgbVec b = sample(base, width, height, hn::Add(x, hn::Div(dx, six)), hn::Add(y, hn::Div(dy, six)));
  const RgbVec c = sample(base, width, height, hn::Sub(x, hn::Mul(dx, half)), hn::Sub(y, hn::Mul(dy, half)));
  const RgbVec d = sample(base, width, height, hn::Add(x, hn::Mul(dx, half)), hn::Add(y, hn::Mul(dy, half)));
  const RgbVec near{hn::Mul(half, hn::Add(a.r, b.r)), hn::Mul(half, hn::Add(a.g, b.g)),
                    hn::Mul(half, hn::Add(a.b, b.b))};
  const RgbVec wide{hn::Add(hn::Mul(half, near.r), hn::Mul(quarter, hn::Add(c.r, d.r))),
                    hn::Add(hn::Mul(half, near.g), hn::Mul(quarter, hn::Add(c.g, d.g))),
                    hn::Add(hn::Mul(half, near.b), hn::Mul(quarter, hn::Add(c.b, d.b)))};
  // Rec. 601 luma, 0..1, in the plain loop's order.
  const VF wide_luma = hn::Mul(hn::Add(hn::Add(hn::Mul(hn::Set(df, 77.0f), wide.r), hn::Mul(hn::Set(df, 150.0f), wide.g)),
                                       hn::Mul(hn::Set(df, 29.0f), wide.b)),
                               hn::Set(df, 1.0f / (256.0f * 255.0f)));
  const auto outside = hn::Or(hn::Lt(wide_luma, hn::LoadU(df, los)), hn::Gt(wide_luma, hn::LoadU(df, his)));
  const VI r = to_byte(hn::IfThenElse(outside, near.r, wide.r));
  const VI g = to_byte(hn::IfThenElse(outside, near.g, wide.g));
  const VI bl = to_byte(hn::IfThenElse(outside, near.b, wide.b));
  const VI packed = hn::Or(r, hn::Or(hn::ShiftLeft<8>(g), hn::ShiftLeft<16>(bl)));
  hn::StoreU(hn::BitCast(DU(), packed), DU(), out);
}

void BlendEdges(const std::uint8_t* rgb, int width, int height, FxaaEdges& e) {
  const std::int32_t* base = reinterpret_cast<const std::int32_t*>(rgb);
  const std::size_t count = e.size(), lanes = hn::Lanes(DF());
  e.blended.resize(count);
  std::size_t i = 0;
  for (; i + lanes <= count; i += lanes) {
    blend_lanes(base, width, height, &e.x[i], &e.y[i], &e.dx[i], &e.dy[i], &e.luma_lo[i],
                &e.luma_hi[i], &e.blended[i]);
  }
  if (i == count) return;
  // The last few, padded with pixel (1, 1) and no span.
  constexpr std::size_t kMaxLanes = HWY_MAX_BYTES / sizeof(float);
  std::int32_t xs[kMaxLanes], ys[kMaxLanes];
  float dxs[kMaxLanes] = {}, dys[kMaxLanes] = {}, los[kMaxLanes] = {}, his[kMaxLanes] = {};
  std::uint32_t out[kMaxLanes];
  std::fill_n(xs, kMaxLanes, 1);
  std::fill_n(ys, kMaxLanes, 1);
  const std::size_t rest = count - i;
  std::copy_n(&e.x[i], rest, xs);
  std::copy_n(&e.y[i], rest, ys);
  std::copy_n(&e.dx[i], rest, dxs);
  std::copy_n(&e.dy[i], rest, dys);
  std::copy_n(&e.luma_lo[i], rest, los);
  std::copy_n(&e.luma_hi[i], rest, his);
  blend_lanes(base, width, height, xs, ys, dxs, dys, los, his, out);
  std::copy_n(out, rest, &e.blended[i]);
}

}  // namespace HWY_NAMESPACE
}  // namespace tissu
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace tissu {

HWY_EXPORT(BlendEdges);

void FxaaEdges::clear() {
  for (auto* v : {&x, &y}) v->clear();
  for (auto* v : {&dx, &dy, &luma_lo, &luma_hi}) v->clear();
  blended.clear();
}

void fxaa_blend_edges(const std::uint8_t* rgb, int width, int height, FxaaEdges& edges) {
  HWY_DYNAMIC_DISPATCH(BlendEdges)(rgb, width, height, edges);
}

}  // namespace tissu
#endif  // HWY_ONCE
