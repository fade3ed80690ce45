// See pixel_simd.h. Compiled once per instruction set by Highway's foreach_target (this
// file includes itself).
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "render/image/pixel_simd.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include "render/image/pixel_simd.h"

HWY_BEFORE_NAMESPACE();
namespace tissu {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

void RgbaToRgb(const std::uint8_t* rgba, std::uint8_t* rgb, std::size_t pixels) {
  std::size_t i = 0;
#if HWY_TARGET != HWY_SCALAR
  const hn::ScalableTag<std::uint8_t> d;
  const std::size_t n = hn::Lanes(d);
  for (; i + n <= pixels; i += n) {
    hn::Vec<decltype(d)> r, g, b, a;
    hn::LoadInterleaved4(d, rgba + 4 * i, r, g, b, a);
    hn::StoreInterleaved3(r, g, b, d, rgb + 3 * i);
  }
#endif
  for (; i < pixels; ++i) {
    rgb[3 * i] = rgba[4 * i];
    rgb[3 * i + 1] = rgba[4 * i + 1];
    rgb[3 * i + 2] = rgba[4 * i + 2];
  }
}

void RgbLuma(const std::uint8_t* rgb, std::uint8_t* luma, std::size_t pixels) {
  std::size_t i = 0;
#if HWY_TARGET != HWY_SCALAR
  using D8 = hn::ScalableTag<std::uint8_t>;
  using DH8 = hn::Half<D8>;
  using D16 = hn::Rebind<std::uint16_t, DH8>;
  using DI16 = hn::RebindToSigned<D16>;
  const D8 d8;
  const DH8 dh8;
  const D16 d16;
  const DI16 di16;
  const std::size_t n = hn::Lanes(d8), half = n / 2;
  const auto kr = hn::Set(d16, std::uint16_t(77)), kg = hn::Set(d16, std::uint16_t(150));
  const auto kb = hn::Set(d16, std::uint16_t(29)), rounding = hn::Set(d16, std::uint16_t(128));
  // At most 256 * 255 + 128: fits 16 bits; the result at most 255.
  auto part = [&](hn::Vec<DH8> r, hn::Vec<DH8> g, hn::Vec<DH8> b) {
    const auto sum = hn::Add(hn::Add(hn::Mul(hn::PromoteTo(d16, r), kr), hn::Mul(hn::PromoteTo(d16, g), kg)),
                             hn::Add(hn::Mul(hn::PromoteTo(d16, b), kb), rounding));
    return hn::DemoteTo(dh8, hn::BitCast(di16, hn::ShiftRight<8>(sum)));
  };
  for (; i + n <= pixels; i += n) {
    hn::Vec<D8> r, g, b;
    hn::LoadInterleaved3(d8, rgb + 3 * i, r, g, b);
    hn::StoreU(part(hn::LowerHalf(dh8, r), hn::LowerHalf(dh8, g), hn::LowerHalf(dh8, b)), dh8, luma + i);
    hn::StoreU(part(hn::UpperHalf(dh8, r), hn::UpperHalf(dh8, g), hn::UpperHalf(dh8, b)), dh8, luma + i + half);
  }
#endif
  for (; i < pixels; ++i) {
    const std::uint8_t* p = rgb + 3 * i;
    luma[i] = static_cast<std::uint8_t>((77u * p[0] + 150u * p[1] + 29u * p[2] + 128u) >> 8);
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace tissu
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace tissu {

HWY_EXPORT(RgbaToRgb);
HWY_EXPORT(RgbLuma);

void rgba_to_rgb(const std::uint8_t* rgba, std::uint8_t* rgb, std::size_t pixels) {
  HWY_DYNAMIC_DISPATCH(RgbaToRgb)(rgba, rgb, pixels);
}

void rgb_luma(const std::uint8_t* rgb, std::uint8_t* luma, std::size_t pixels) {
  HWY_DYNAMIC_DISPATCH(RgbLuma)(rgb, luma, pixels);
}

}  // namespace tissu
#endif  // HWY_ONCE
