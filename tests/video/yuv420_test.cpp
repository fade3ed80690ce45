#include "video/yuv420.h"

#include <gtest/gtest.h>
#include <hwy/targets.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

namespace tissu {
namespace {

struct Planes {
  int width, height;
  std::vector<std::uint8_t> y, u, v;
  Planes(int w, int h) : width(w), height(h), y(std::size_t(w) * h, 7), u(std::size_t(w / 2) * (h / 2), 7), v(u) {}
};

Planes convert(const std::vector<std::uint8_t>& rgb, int width, int height, bool scalar) {
  Planes p(width, height);
  (scalar ? rgb_to_yuv420_scalar : rgb_to_yuv420)(rgb.data(), width * 3, width, height, p.y.data(), width,
                                                  p.u.data(), width / 2, p.v.data(), width / 2);
  return p;
}

std::vector<std::uint8_t> noise(int width, int height, unsigned seed) {
  std::vector<std::uint8_t> rgb(std::size_t(width) * height * 3);
  std::mt19937 random(seed);
  for (auto& c : rgb) c = static_cast<std::uint8_t>(random() & 255);
  return rgb;
}

TEST(RgbToYuv420, EveryInstructionSetGivesTheBytesOfTheScalarLoop) {
  for (int width : {2, 6, 18, 64, 322, 1280}) {
    const int height = 6;
    const std::vector<std::uint8_t> rgb = noise(width, height, unsigned(width));
    const Planes reference = convert(rgb, width, height, true);
    for (const std::int64_t target : hwy::SupportedAndGeneratedTargets()) {
      hwy::SetSupportedTargetsForTest(target);
      const Planes p = convert(rgb, width, height, false);
      EXPECT_EQ(p.y, reference.y) << hwy::TargetName(target) << " width " << width;
      EXPECT_EQ(p.u, reference.u) << hwy::TargetName(target) << " width " << width;
      EXPECT_EQ(p.v, reference.v) << hwy::TargetName(target) << " width " << width;
    }
    hwy::SetSupportedTargetsForTest(0);
  }
}

TEST(RgbToYuv420, GreysKeepNeutralChromaAndTheLimitedRange) {
  for (int level : {0, 1, 64, 128, 200, 255}) {
    const std::vector<std::uint8_t> rgb(4 * 2 * 3, static_cast<std::uint8_t>(level));
    const Planes p = convert(rgb, 4, 2, false);
    const int expected_y = int(std::lround(16 + 219.0 * level / 255.0));
    for (std::uint8_t y : p.y) EXPECT_EQ(int(y), expected_y) << level;
    for (std::uint8_t c : p.u) EXPECT_EQ(int(c), 128) << level;
    for (std::uint8_t c : p.v) EXPECT_EQ(int(c), 128) << level;
  }
}

TEST(RgbToYuv420, MatchesBt709WithinOneStep) {
  const int width = 64, height = 4;
  const std::vector<std::uint8_t> rgb = noise(width, height, 5);
  const Planes p = convert(rgb, width, height, false);
  for (int row = 0; row < height; ++row) {
    for (int x = 0; x < width; ++x) {
      const std::uint8_t* c = &rgb[(std::size_t(row) * width + x) * 3];
      const double y = 16 + 219.0 / 255.0 * (0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]);
      EXPECT_NEAR(p.y[std::size_t(row) * width + x], y, 0.51) << x << ", " << row;
    }
  }
  for (int row = 0; row < height / 2; ++row) {
    for (int x = 0; x < width / 2; ++x) {
      double mean[3] = {0, 0, 0};  // of the 2x2 block
      for (int k = 0; k < 4; ++k) {
        const std::uint8_t* c = &rgb[(std::size_t(2 * row + k / 2) * width + 2 * x + k % 2) * 3];
        for (int j = 0; j < 3; ++j) mean[j] += 0.25 * c[j];
      }
      const double luma = 0.2126 * mean[0] + 0.7152 * mean[1] + 0.0722 * mean[2];
      const double u = 128 + 224.0 / 255.0 * (mean[2] - luma) / 1.8556;
      const double v = 128 + 224.0 / 255.0 * (mean[0] - luma) / 1.5748;
      EXPECT_NEAR(p.u[std::size_t(row) * (width / 2) + x], u, 0.51) << x << ", " << row;
      EXPECT_NEAR(p.v[std::size_t(row) * (width / 2) + x], v, 0.51) << x << ", " << row;
    }
  }
}

}  // namespace
}  // namespace tissu
