#include "render/image/fxaa_edges_simd.h"

#include <gtest/gtest.h>
#include <hwy/targets.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <vector>

namespace tissu {
namespace {

// The per-pixel loop FXAA used before its edge pixels went to SIMD: the reference bytes.
struct Rgb {
  float r, g, b;
};

Rgb plain_sample(const std::vector<std::uint8_t>& src, int width, int height, float x, float y) {
  x = std::clamp(x, 0.0f, float(width - 1));
  y = std::clamp(y, 0.0f, float(height - 1));
  const int x0 = std::min(int(x), width - 2), y0 = std::min(int(y), height - 2);
  const float fx = x - x0, fy = y - y0;
  const std::uint8_t* a = &src[(std::size_t(y0) * width + x0) * 3];
  const std::uint8_t* b = a + 3;
  const std::uint8_t* c = a + std::size_t(width) * 3;
  const std::uint8_t* d = c + 3;
  auto mix = [&](int k) {
    const float top = a[k] + (b[k] - a[k]) * fx;
    const float bottom = c[k] + (d[k] - c[k]) * fx;
    return top + (bottom - top) * fy;
  };
  return {mix(0), mix(1), mix(2)};
}

std::uint32_t plain_blend(const std::vector<std::uint8_t>& rgb, int width, int height,
                          const FxaaEdges& e, std::size_t k) {
  const float x = float(e.x[k]), y = float(e.y[k]), dx = e.dx[k], dy = e.dy[k];
  const Rgb a = plain_sample(rgb, width, height, x - dx / 6.0f, y - dy / 6.0f);
  const Rgb b = plain_sample(rgb, width, height, x + dx / 6.0f, y + dy / 6.0f);
  const Rgb near{0.5f * (a.r + b.r), 0.5f * (a.g + b.g), 0.5f * (a.b + b.b)};
  const Rgb c = plain_sample(rgb, width, height, x - dx * 0.5f, y - dy * 0.5f);
  const Rgb d = plain_sample(rgb, width, height, x + dx * 0.5f, y + dy * 0.5f);
  const Rgb wide{0.5f * near.r + 0.25f * (c.r + d.r), 0.5f * near.g + 0.25f * (c.g + d.g),
                 0.5f * near.b + 0.25f * (c.b + d.b)};
  const float luma = (77.0f * wide.r + 150.0f * wide.g + 29.0f * wide.b) * (1.0f / (256.0f * 255.0f));
  const Rgb& out = (luma < e.luma_lo[k] || luma > e.luma_hi[k]) ? near : wide;
  auto byte = [](float v) { return std::uint32_t(std::uint8_t(std::clamp(v + 0.5f, 0.0f, 255.0f))); };
  return byte(out.r) | byte(out.g) << 8 | byte(out.b) << 16;
}

// Every instruction set, for any number of edge pixels (whole vectors and the rest), and
// spans reaching past the image's sides, gives the plain loop's bytes.
TEST(FxaaEdges, BlendsAsThePlainLoopOnEveryInstructionSet) {
  const int width = 37, height = 23;
  std::mt19937 random(5);
  std::vector<std::uint8_t> rgb(std::size_t(width) * height * 3);
  for (auto& c : rgb) c = static_cast<std::uint8_t>(random() & 255);
  std::uniform_real_distribution<float> span(-8.0f, 8.0f), luma(0.0f, 1.0f);
  for (std::size_t count : {std::size_t(1), std::size_t(7), std::size_t(64), std::size_t(301)}) {
    FxaaEdges edges;
    for (std::size_t k = 0; k < count; ++k) {
      edges.x.push_back(1 + int(random() % (width - 2)));
      edges.y.push_back(1 + int(random() % (height - 2)));
      edges.dx.push_back(k % 5 == 0 ? 8.0f : span(random));
      edges.dy.push_back(k % 7 == 0 ? -8.0f : span(random));
      const float a = luma(random), b = luma(random);
      edges.luma_lo.push_back(std::min(a, b));
      edges.luma_hi.push_back(std::max(a, b));
    }
    std::vector<std::uint32_t> expected(count);
    for (std::size_t k = 0; k < count; ++k) expected[k] = plain_blend(rgb, width, height, edges, k);
    for (const std::int64_t target : hwy::SupportedAndGeneratedTargets()) {
      hwy::SetSupportedTargetsForTest(target);
      edges.blended.assign(count, 0xFFFFFFFFu);
      fxaa_blend_edges(rgb.data(), width, height, edges);
      EXPECT_EQ(edges.blended, expected) << hwy::TargetName(target) << ", " << count << " pixels";
    }
    hwy::SetSupportedTargetsForTest(0);
  }
}

}  // namespace
}  // namespace tissu
