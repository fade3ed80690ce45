#include "render/image/pixel_simd.h"

#include <gtest/gtest.h>
#include <hwy/targets.h>

#include <cstdint>
#include <random>
#include <vector>

namespace tissu {
namespace {

std::vector<std::uint8_t> noise(std::size_t bytes, unsigned seed) {
  std::vector<std::uint8_t> v(bytes);
  std::mt19937 random(seed);
  for (auto& c : v) c = static_cast<std::uint8_t>(random() & 255);
  return v;
}

// Every instruction set, and every length (whole vectors and the rest), gives the bytes of
// the plain loops the renderer used before.
TEST(PixelSimd, RgbaToRgbDropsAlphaOnEveryInstructionSet) {
  for (std::size_t pixels : {std::size_t(1), std::size_t(15), std::size_t(64), std::size_t(1283)}) {
    const std::vector<std::uint8_t> rgba = noise(4 * pixels, unsigned(pixels));
    std::vector<std::uint8_t> expected(3 * pixels);
    for (std::size_t i = 0; i < pixels; ++i) {
      for (int c = 0; c < 3; ++c) expected[3 * i + c] = rgba[4 * i + c];
    }
    for (const std::int64_t target : hwy::SupportedAndGeneratedTargets()) {
      hwy::SetSupportedTargetsForTest(target);
      std::vector<std::uint8_t> rgb(3 * pixels, 7);
      rgba_to_rgb(rgba.data(), rgb.data(), pixels);
      EXPECT_EQ(rgb, expected) << hwy::TargetName(target) << ", " << pixels << " pixels";
    }
    hwy::SetSupportedTargetsForTest(0);
  }
}

TEST(PixelSimd, LumaIsRec601In256thsOnEveryInstructionSet) {
  for (std::size_t pixels : {std::size_t(1), std::size_t(15), std::size_t(64), std::size_t(1283)}) {
    std::vector<std::uint8_t> rgb = noise(3 * pixels, unsigned(pixels) + 1);
    for (int c = 0; c < 3; ++c) rgb[c] = 255;  // the largest sum
    std::vector<std::uint8_t> expected(pixels);
    for (std::size_t i = 0; i < pixels; ++i) {
      const std::uint8_t* p = &rgb[3 * i];
      expected[i] = static_cast<std::uint8_t>((77u * p[0] + 150u * p[1] + 29u * p[2] + 128u) >> 8);
    }
    EXPECT_EQ(expected[0], 255);
    for (const std::int64_t target : hwy::SupportedAndGeneratedTargets()) {
      hwy::SetSupportedTargetsForTest(target);
      std::vector<std::uint8_t> luma(pixels, 7);
      rgb_luma(rgb.data(), luma.data(), pixels);
      EXPECT_EQ(luma, expected) << hwy::TargetName(target) << ", " << pixels << " pixels";
    }
    hwy::SetSupportedTargetsForTest(0);
  }
}

}  // namespace
}  // namespace tissu
