// See fxaa_edges_simd.h. Compiled once per instruction set by Highway's foreach_target
// (this file includes itself), with -ffp-contract=off (src/render/CMakeLists.txt).
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "render/image/fxaa_edges_simd.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include <algorithm>
#include <stdexcept>

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

constexpr float kSpanMax = 8.0f;              // pixels
constexpr float kReduceMul = 1.0f / 8.0f;
constexpr float kReduceMin = 1.0f / 128.0f;
constexpr float kByte = 1.0f / 255.0f;         // luma byte to 0..1

// Row y's flags, 1 on an edge pixel: over the pixel and its four direct neighbours, the luma
// spans at least max(edge_min, the brightest / 8). From x = 1 to the image's last pixel but
// one; the flags after it, to a whole vector of floats past it, are 0.
HWY_INLINE void flag_row(const std::uint8_t* row, const std::uint8_t* up, const std::uint8_t* down,
                         int width, std::uint8_t edge_min, std::uint8_t* flags) {
  const hn::ScalableTag<std::uint8_t> d8;
  const int n = static_cast<int>(hn::Lanes(d8));
  const auto floor = hn::Set(d8, edge_min), one = hn::Set(d8, std::uint8_t(1));
  for (int x = 1; x < width - 1; x += n) {
    const auto m = hn::LoadU(d8, row + x), w = hn::LoadU(d8, row + x - 1), e = hn::LoadU(d8, row + x + 1);
    const auto u = hn::LoadU(d8, up + x), d = hn::LoadU(d8, down + x);
    const auto hi = hn::Max(hn::Max(hn::Max(m, u), hn::Max(d, w)), e);
    const auto lo = hn::Min(hn::Min(hn::Min(m, u), hn::Min(d, w)), e);
    const auto threshold = hn::Max(floor, hn::ShiftRight<3>(hi));
    // hi - lo >= threshold: the threshold less the span saturates to 0.
    const auto edge = hn::Eq(hn::SaturatedSub(threshold, hn::Sub(hi, lo)), hn::Zero(d8));
    hn::StoreU(hn::IfThenElseZero(edge, one), d8, flags + x);
  }
  std::fill_n(flags + width - 1, n + hn::Lanes(DF()), std::uint8_t(0));
}

// The flagged pixels of row y, a vector of pixels at a time: their span along the edge
// (across the 2x2 blocks' luma gradient) and their 3x3 block's luma range.
HWY_INLINE void spans_of_row(const std::uint8_t* row, const std::uint8_t* up, const std::uint8_t* down,
                             int width, int y, const std::uint8_t* flags, FxaaEdges& e) {
  const DF df;
  const DI di;
  const hn::Rebind<std::uint8_t, DI> d8;
  const int n = static_cast<int>(hn::Lanes(df));
  auto load = [&](const std::uint8_t* p) { return hn::PromoteTo(di, hn::LoadU(d8, p)); };
  for (int x = 1; x < width - 1; x += n) {
    const auto flagged = hn::Ne(load(flags + x), hn::Zero(di));
    if (hn::AllFalse(di, flagged)) continue;
    const VI ul = load(up + x - 1), u = load(up + x), ur = load(up + x + 1);
    const VI w = load(row + x - 1), m = load(row + x), east = load(row + x + 1);
    const VI dl = load(down + x - 1), d = load(down + x), dr = load(down + x + 1);
    const VI lo = hn::Min(hn::Min(hn::Min(m, u), hn::Min(d, w)), east);
    const VI hi = hn::Max(hn::Max(hn::Max(m, u), hn::Max(d, w)), east);
    // The four 2x2 blocks around the pixel, as the shader's half-pixel bilinear taps.
    const VF quarter_byte = hn::Set(df, 0.25f * kByte);
    const VF nw = hn::Mul(quarter_byte, hn::ConvertTo(df, hn::Add(hn::Add(hn::Add(ul, u), w), m)));
    const VF ne = hn::Mul(quarter_byte, hn::ConvertTo(df, hn::Add(hn::Add(hn::Add(u, ur), m), east)));
    const VF sw = hn::Mul(quarter_byte, hn::ConvertTo(df, hn::Add(hn::Add(hn::Add(w, m), dl), d)));
    const VF se = hn::Mul(quarter_byte, hn::ConvertTo(df, hn::Add(hn::Add(hn::Add(m, east), d), dr)));
    const VF byte = hn::Set(df, kByte);
    const VF block_lo = hn::Mul(byte, hn::ConvertTo(df, hn::Min(lo, hn::Min(hn::Min(ul, ur), hn::Min(dl, dr)))));
    const VF block_hi = hn::Mul(byte, hn::ConvertTo(df, hn::Max(hi, hn::Max(hn::Max(ul, ur), hn::Max(dl, dr)))));
    // Across the luma gradient (gx, gy) is the edge's direction (gy, -gx); y grows down.
    const VF dx = hn::Sub(hn::Add(sw, se), hn::Add(nw, ne));
    const VF dy = hn::Sub(hn::Add(nw, sw), hn::Add(ne, se));
    const VF sum = hn::Add(hn::Add(hn::Add(nw, ne), sw), se);
    const VF reduce = hn::Max(hn::Mul(hn::Mul(sum, hn::Set(df, 0.25f)), hn::Set(df, kReduceMul)),
                              hn::Set(df, kReduceMin));
    const VF scale = hn::Div(hn::Set(df, 1.0f), hn::Add(hn::Min(hn::Abs(dx), hn::Abs(dy)), reduce));
    const VF low = hn::Set(df, -kSpanMax), high = hn::Set(df, kSpanMax);
    const VF span_x = hn::Min(hn::Max(hn::Mul(dx, scale), low), high);
    const VF span_y = hn::Min(hn::Max(hn::Mul(dy, scale), low), high);
    e.make_room(static_cast<std::size_t>(n));
    const auto fm = hn::RebindMask(df, flagged);
    // Compress, then a whole-vector store (room was made): the compressing store itself is
    // microcoded and many times slower on some processors (AMD Zen 4).
    const std::size_t at = e.count;
    hn::StoreU(hn::Compress(hn::Iota(di, x), flagged), di, &e.x[at]);
    hn::StoreU(hn::Set(di, y), di, &e.y[at]);
    hn::StoreU(hn::Compress(span_x, fm), df, &e.dx[at]);
    hn::StoreU(hn::Compress(span_y, fm), df, &e.dy[at]);
    hn::StoreU(hn::Compress(block_lo, fm), df, &e.luma_lo[at]);
    hn::StoreU(hn::Compress(block_hi, fm), df, &e.luma_hi[at]);
    e.count = at + hn::CountTrue(di, flagged);
  }
}

void FindEdges(const std::uint8_t* luma, int width, int height, std::uint8_t edge_min,
               std::vector<std::uint8_t>& row_flags, FxaaEdges& e) {
  // A row's scan reads a vector of bytes and one more past the image's last pixel.
  if (hn::Lanes(hn::ScalableTag<std::uint8_t>()) + 1 > fxaa_luma_padding()) {
    throw std::logic_error("fxaa_find_edges: vectors wider than the luma padding");
  }
  e.count = 0;
  row_flags.resize(static_cast<std::size_t>(width) + 2 * HWY_MAX_BYTES);
  for (int y = 1; y + 1 < height; ++y) {
    const std::uint8_t* row = luma + std::size_t(y) * width;
    flag_row(row, row - width, row + width, width, edge_min, row_flags.data());
    spans_of_row(row, row - width, row + width, width, y, row_flags.data(), e);
  }
}

void BlendEdges(const std::uint8_t* rgb, int width, int height, FxaaEdges& e) {
  const std::int32_t* base = reinterpret_cast<const std::int32_t*>(rgb);
  const std::size_t count = e.size(), lanes = hn::Lanes(DF());
  if (e.blended.size() < count) e.blended.resize(count);
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

HWY_EXPORT(FindEdges);
HWY_EXPORT(BlendEdges);

void FxaaEdges::make_room(std::size_t more) {
  const std::size_t need = count + more;
  if (x.size() >= need) return;
  const std::size_t size = std::max({need, 2 * x.size(), std::size_t(4096)});
  for (auto* v : {&x, &y}) v->resize(size);
  for (auto* v : {&dx, &dy, &luma_lo, &luma_hi}) v->resize(size);
}

void FxaaEdges::push(std::int32_t px, std::int32_t py, float span_x, float span_y, float lo, float hi) {
  make_room(1);
  x[count] = px;
  y[count] = py;
  dx[count] = span_x;
  dy[count] = span_y;
  luma_lo[count] = lo;
  luma_hi[count] = hi;
  ++count;
}

// More than a row's scan reads past the image (a vector of bytes and one more) on x86 and
// Arm; FindEdges checks it.
std::size_t fxaa_luma_padding() { return 256; }

void fxaa_find_edges(const std::uint8_t* luma, int width, int height, std::uint8_t edge_min,
                     std::vector<std::uint8_t>& row_flags, FxaaEdges& edges) {
  HWY_DYNAMIC_DISPATCH(FindEdges)(luma, width, height, edge_min, row_flags, edges);
}

void fxaa_blend_edges(const std::uint8_t* rgb, int width, int height, FxaaEdges& edges) {
  HWY_DYNAMIC_DISPATCH(BlendEdges)(rgb, width, height, edges);
}

}  // namespace tissu
#endif  // HWY_ONCE
