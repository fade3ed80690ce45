// FXAA on the processor (render/image/fxaa.h): flat areas untouched, aliased edges brought closer
// to their true coverage.
#include "render/image/fxaa.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace tissu {
namespace {

constexpr int kW = 96, kH = 64;

// A dark half-plane below the line y = slope * x + offset on a light background: with
// `samples` x `samples` samples per pixel (1 = aliased staircase; many = true coverage).
std::vector<std::uint8_t> half_plane(double slope, double offset, int samples) {
  std::vector<std::uint8_t> rgb(kW * kH * 3);
  for (int y = 0; y < kH; ++y) {
    for (int x = 0; x < kW; ++x) {
      int inside = 0;
      for (int i = 0; i < samples; ++i) {
        for (int j = 0; j < samples; ++j) {
          const double sx = x + (i + 0.5) / samples, sy = y + (j + 0.5) / samples;
          inside += sy > slope * sx + offset;
        }
      }
      const double dark = double(inside) / (samples * samples);
      const auto value = static_cast<std::uint8_t>(std::lround(220.0 - 180.0 * dark));
      for (int c = 0; c < 3; ++c) rgb[(y * kW + x) * 3 + c] = value;
    }
  }
  return rgb;
}

double rms_difference(const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b) {
  double sum = 0.0;
  for (size_t i = 0; i < a.size(); ++i) sum += (double(a[i]) - b[i]) * (double(a[i]) - b[i]);
  return std::sqrt(sum / a.size());
}

TEST(Fxaa, FlatAndSmoothImagesStayTheSame) {
  std::vector<std::uint8_t> rgb(kW * kH * 3);
  for (int y = 0; y < kH; ++y) {
    for (int x = 0; x < kW; ++x) {
      for (int c = 0; c < 3; ++c) rgb[(y * kW + x) * 3 + c] = static_cast<std::uint8_t>(40 + x + c);
    }
  }
  const std::vector<std::uint8_t> before = rgb;
  FxaaScratch scratch;
  fxaa_rgb(rgb, kW, kH, scratch);
  EXPECT_EQ(rgb, before);
}

TEST(Fxaa, AliasedEdgesComeCloserToTheirCoverage) {
  FxaaScratch scratch;
  for (double slope : {0.2, 0.3, 0.45, 1.0, 2.5, -0.2, -0.3, -1.0, -2.5}) {
    const double offset = slope > 0 ? 10.0 : 50.0;
    std::vector<std::uint8_t> aliased = half_plane(slope, offset, 1);
    const std::vector<std::uint8_t> truth = half_plane(slope, offset, 16);
    const double before = rms_difference(aliased, truth);
    fxaa_rgb(aliased, kW, kH, scratch);
    const double after = rms_difference(aliased, truth);
    // Steep and diagonal edges improve by 30-50%, near-horizontal ones (slope 0.2) by about
    // 20%: the filter looks 8 pixels along an edge at most.
    EXPECT_LT(after, 0.85 * before) << "slope " << slope << ": " << before << " -> " << after;
    // Far from the edge nothing changes.
    const std::vector<std::uint8_t> original = half_plane(slope, offset, 1);
    for (int y = 0; y < kH; ++y) {
      for (int x = 0; x < kW; ++x) {
        const double distance = std::abs(y + 0.5 - slope * (x + 0.5) - offset) / std::hypot(1.0, slope);
        if (distance > 10.0) {
          ASSERT_EQ(aliased[(y * kW + x) * 3], original[(y * kW + x) * 3]) << x << " " << y;
        }
      }
    }
  }
}

TEST(Fxaa, TinyImagesAreLeftAlone) {
  std::vector<std::uint8_t> rgb = {0, 0, 0, 255, 255, 255, 0, 0, 0, 255, 255, 255};
  const std::vector<std::uint8_t> before = rgb;
  FxaaScratch scratch;
  fxaa_rgb(rgb, 2, 2, scratch);
  EXPECT_EQ(rgb, before);
}

}  // namespace
}  // namespace tissu
