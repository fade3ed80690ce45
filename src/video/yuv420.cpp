// RGB to YUV 4:2:0; see yuv420.h. Compiled once per instruction set by Highway's
// foreach_target (this file includes itself). Integer arithmetic only, so every target
// writes the bytes of the scalar loop.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "video/yuv420.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include "video/yuv420.h"

#ifndef TISSU_YUV420_COEFFICIENTS
#define TISSU_YUV420_COEFFICIENTS
namespace tissu {
namespace yuv420 {

// BT.709 limited range, times 65536. Luma: 219/255 (0.2126, 0.7152, 0.0722), plus 16.
constexpr std::uint32_t kYr = 11966, kYg = 40254, kYb = 4064;
// Chroma: 224/255 times (B - Y) / 1.8556 and (R - Y) / 1.5748, plus 128; each row sums to 0,
// so grey stays exactly 128.
constexpr std::int32_t kUr = -6596, kUg = -22188, kUb = 28784;
constexpr std::int32_t kVr = 28784, kVg = -26145, kVb = -2639;
// Chroma from the sums of a 2x2 block: (c . sum + kChromaOffset) >> 18 (a mean of 4, /65536).
constexpr std::int32_t kChromaOffset = (128 * 4 + 2) * 65536;

// Each term as the SIMD code computes it: the high 16 bits of (c << 8) * coefficient.
inline std::uint32_t luma_term(std::uint32_t c, std::uint32_t k) { return ((c << 8) * k) >> 16; }

inline std::uint8_t luma(std::uint32_t r, std::uint32_t g, std::uint32_t b) {
  return static_cast<std::uint8_t>((luma_term(r, kYr) + luma_term(g, kYg) + luma_term(b, kYb) + 16 * 256 + 128) >> 8);
}

inline std::uint8_t chroma(std::int32_t sr, std::int32_t sg, std::int32_t sb, std::int32_t kr, std::int32_t kg,
                           std::int32_t kb) {
  const std::int32_t c = (kr * sr + kg * sg + kb * sb + kChromaOffset) >> 18;
  return static_cast<std::uint8_t>(c < 0 ? 0 : c > 255 ? 255 : c);
}

// Columns [x0, width) of the row pair starting at `r0` (x0 even).
inline void row_pair_scalar(const std::uint8_t* r0, const std::uint8_t* r1, int x0, int width, std::uint8_t* y0,
                            std::uint8_t* y1, std::uint8_t* u, std::uint8_t* v) {
  for (int x = x0; x < width; x += 2) {
    const std::uint8_t* a = r0 + 3 * x;
    const std::uint8_t* b = r1 + 3 * x;
    y0[x] = luma(a[0], a[1], a[2]);
    y0[x + 1] = luma(a[3], a[4], a[5]);
    y1[x] = luma(b[0], b[1], b[2]);
    y1[x + 1] = luma(b[3], b[4], b[5]);
    const std::int32_t sr = a[0] + a[3] + b[0] + b[3];
    const std::int32_t sg = a[1] + a[4] + b[1] + b[4];
    const std::int32_t sb = a[2] + a[5] + b[2] + b[5];
    u[x / 2] = chroma(sr, sg, sb, kUr, kUg, kUb);
    v[x / 2] = chroma(sr, sg, sb, kVr, kVg, kVb);
  }
}

}  // namespace yuv420
}  // namespace tissu
#endif

HWY_BEFORE_NAMESPACE();
namespace tissu {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

void RgbToYuv420(const std::uint8_t* rgb, int rgb_stride, int width, int height, std::uint8_t* y, int y_stride,
                 std::uint8_t* u, int u_stride, std::uint8_t* v, int v_stride) {
#if HWY_TARGET == HWY_SCALAR
  rgb_to_yuv420_scalar(rgb, rgb_stride, width, height, y, y_stride, u, u_stride, v, v_stride);
#else
  using D8 = hn::ScalableTag<std::uint8_t>;
  using DH8 = hn::Half<D8>;
  using D16 = hn::Rebind<std::uint16_t, DH8>;
  using DI16 = hn::RebindToSigned<D16>;
  using D32 = hn::RepartitionToWide<D16>;
  using DI32 = hn::RebindToSigned<D32>;
  using DQ8 = hn::Rebind<std::uint8_t, D32>;
  const D8 d8;
  const DH8 dh8;
  const D16 d16;
  const DI16 di16;
  const D32 d32;
  const DI32 di32;
  const DQ8 dq8;
  const int simd_end = width - width % int(hn::Lanes(d8));
  const int step = int(hn::Lanes(d8));
  const int half = step / 2;

  const auto yr = hn::Set(d16, std::uint16_t(yuv420::kYr));
  const auto yg = hn::Set(d16, std::uint16_t(yuv420::kYg));
  const auto yb = hn::Set(d16, std::uint16_t(yuv420::kYb));
  const auto y_offset = hn::Set(d16, std::uint16_t(16 * 256 + 128));
  const auto low16 = hn::Set(d32, 0xFFFFu);
  const auto offset = hn::Set(di32, yuv420::kChromaOffset);

  auto luma = [&](hn::Vec<DH8> r, hn::Vec<DH8> g, hn::Vec<DH8> b) {
    const auto r16 = hn::ShiftLeft<8>(hn::PromoteTo(d16, r));
    const auto g16 = hn::ShiftLeft<8>(hn::PromoteTo(d16, g));
    const auto b16 = hn::ShiftLeft<8>(hn::PromoteTo(d16, b));
    const auto sum = hn::Add(hn::Add(hn::MulHigh(r16, yr), hn::MulHigh(g16, yg)),
                             hn::Add(hn::MulHigh(b16, yb), y_offset));
    return hn::DemoteTo(dh8, hn::BitCast(di16, hn::ShiftRight<8>(sum)));  // at most 235
  };
  // Sums of the 2x2 blocks of one colour: vertical pairs in 16 bits, then horizontal
  // neighbours (the two halves of a 32-bit lane).
  auto block_sums = [&](hn::Vec<DH8> top, hn::Vec<DH8> bottom) {
    const auto column = hn::BitCast(d32, hn::Add(hn::PromoteTo(d16, top), hn::PromoteTo(d16, bottom)));
    return hn::BitCast(di32, hn::Add(hn::And(column, low16), hn::ShiftRight<16>(column)));
  };
  auto chroma = [&](hn::Vec<DI32> sr, hn::Vec<DI32> sg, hn::Vec<DI32> sb, std::int32_t kr, std::int32_t kg,
                    std::int32_t kb) {
    const auto c = hn::Add(hn::Add(hn::Mul(sr, hn::Set(di32, kr)), hn::Mul(sg, hn::Set(di32, kg))),
                           hn::Add(hn::Mul(sb, hn::Set(di32, kb)), offset));
    return hn::DemoteTo(dq8, hn::ShiftRight<18>(c));
  };

  for (int row = 0; row + 1 < height; row += 2) {
    const std::uint8_t* r0 = rgb + std::size_t(row) * rgb_stride;
    const std::uint8_t* r1 = r0 + rgb_stride;
    std::uint8_t* y0 = y + std::size_t(row) * y_stride;
    std::uint8_t* y1 = y0 + y_stride;
    std::uint8_t* u_row = u + std::size_t(row / 2) * u_stride;
    std::uint8_t* v_row = v + std::size_t(row / 2) * v_stride;
    for (int x = 0; x < simd_end; x += step) {
      hn::Vec<D8> ra, ga, ba, rb, gb, bb;
      hn::LoadInterleaved3(d8, r0 + 3 * x, ra, ga, ba);
      hn::LoadInterleaved3(d8, r1 + 3 * x, rb, gb, bb);
      for (int part = 0; part < 2; ++part) {
        const auto pick = [&](hn::Vec<D8> w) { return part == 0 ? hn::LowerHalf(dh8, w) : hn::UpperHalf(dh8, w); };
        const auto r_top = pick(ra), g_top = pick(ga), b_top = pick(ba);
        const auto r_bottom = pick(rb), g_bottom = pick(gb), b_bottom = pick(bb);
        hn::StoreU(luma(r_top, g_top, b_top), dh8, y0 + x + part * half);
        hn::StoreU(luma(r_bottom, g_bottom, b_bottom), dh8, y1 + x + part * half);
        const auto sr = block_sums(r_top, r_bottom);
        const auto sg = block_sums(g_top, g_bottom);
        const auto sb = block_sums(b_top, b_bottom);
        const int c = (x + part * half) / 2;
        hn::StoreU(chroma(sr, sg, sb, yuv420::kUr, yuv420::kUg, yuv420::kUb), dq8, u_row + c);
        hn::StoreU(chroma(sr, sg, sb, yuv420::kVr, yuv420::kVg, yuv420::kVb), dq8, v_row + c);
      }
    }
    yuv420::row_pair_scalar(r0, r1, simd_end, width, y0, y1, u_row, v_row);
  }
#endif
}

}  // namespace HWY_NAMESPACE
}  // namespace tissu
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace tissu {

HWY_EXPORT(RgbToYuv420);

void rgb_to_yuv420(const std::uint8_t* rgb, int rgb_stride, int width, int height, std::uint8_t* y,
                   int y_stride, std::uint8_t* u, int u_stride, std::uint8_t* v, int v_stride) {
  HWY_DYNAMIC_DISPATCH(RgbToYuv420)(rgb, rgb_stride, width, height, y, y_stride, u, u_stride, v, v_stride);
}

void rgb_to_yuv420_scalar(const std::uint8_t* rgb, int rgb_stride, int width, int height, std::uint8_t* y,
                          int y_stride, std::uint8_t* u, int u_stride, std::uint8_t* v, int v_stride) {
  for (int row = 0; row + 1 < height; row += 2) {
    const std::uint8_t* r0 = rgb + std::size_t(row) * rgb_stride;
    yuv420::row_pair_scalar(r0, r0 + rgb_stride, 0, width, y + std::size_t(row) * y_stride,
                            y + std::size_t(row + 1) * y_stride, u + std::size_t(row / 2) * u_stride,
                            v + std::size_t(row / 2) * v_stride);
  }
}

}  // namespace tissu
#endif  // HWY_ONCE
