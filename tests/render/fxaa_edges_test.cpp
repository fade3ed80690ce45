#include "render/image/fxaa_edges_simd.h"

#include <gtest/gtest.h>
#include <hwy/targets.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <string>
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
      const int x = 1 + int(random() % (width - 2)), y = 1 + int(random() % (height - 2));
      const float dx = k % 5 == 0 ? 8.0f : span(random);
      const float dy = k % 7 == 0 ? -8.0f : span(random);
      const float a = luma(random), b = luma(random);
      edges.push(x, y, dx, dy, std::min(a, b), std::max(a, b));
    }
    std::vector<std::uint32_t> expected(count);
    for (std::size_t k = 0; k < count; ++k) expected[k] = plain_blend(rgb, width, height, edges, k);
    for (const std::int64_t target : hwy::SupportedAndGeneratedTargets()) {
      hwy::SetSupportedTargetsForTest(target);
      edges.blended.assign(count, 0xFFFFFFFFu);
      fxaa_blend_edges(rgb.data(), width, height, edges);
      edges.blended.resize(count);
      EXPECT_EQ(edges.blended, expected) << hwy::TargetName(target) << ", " << count << " pixels";
    }
    hwy::SetSupportedTargetsForTest(0);
  }
}

// The per-pixel scan FXAA used before it went to SIMD: the reference edges.
FxaaEdges plain_scan(const std::vector<std::uint8_t>& L, int width, int height, std::uint8_t edge_min) {
  FxaaEdges edges;
  constexpr float k = 1.0f / 255.0f;
  for (int y = 1; y + 1 < height; ++y) {
    const std::uint8_t* row = &L[std::size_t(y) * width];
    const std::uint8_t* up = row - width;
    const std::uint8_t* down = row + width;
    for (int x = 1; x + 1 < width; ++x) {
      const int m = row[x], w = row[x - 1], e = row[x + 1];
      const int hi = std::max({m, int(up[x]), int(down[x]), w, e});
      const int lo = std::min({m, int(up[x]), int(down[x]), w, e});
      if (hi - lo < std::max(int(edge_min), hi >> 3)) continue;
      const float nw = 0.25f * k * (up[x - 1] + up[x] + w + m);
      const float ne = 0.25f * k * (up[x] + up[x + 1] + m + e);
      const float sw = 0.25f * k * (w + m + down[x - 1] + down[x]);
      const float se = 0.25f * k * (m + e + down[x] + down[x + 1]);
      const float block_lo = k * std::min({lo, int(up[x - 1]), int(up[x + 1]), int(down[x - 1]), int(down[x + 1])});
      const float block_hi = k * std::max({hi, int(up[x - 1]), int(up[x + 1]), int(down[x - 1]), int(down[x + 1])});
      const float dx = (sw + se) - (nw + ne);
      const float dy = (nw + sw) - (ne + se);
      const float reduce = std::max((nw + ne + sw + se) * 0.25f * (1.0f / 8.0f), 1.0f / 128.0f);
      const float scale = 1.0f / (std::min(std::fabs(dx), std::fabs(dy)) + reduce);
      edges.push(x, y, std::clamp(dx * scale, -8.0f, 8.0f), std::clamp(dy * scale, -8.0f, 8.0f),
                 block_lo, block_hi);
    }
  }
  return edges;
}

template <class T>
std::vector<T> first(const std::vector<T>& v, std::size_t n) {
  return std::vector<T>(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(n));
}

// Every instruction set finds the plain scan's edge pixels, in its order, with the same
// spans and luma ranges: on noise, on flat images with a few steps (most vectors skipped),
// at widths around and between the vector sizes, and with padding of any value.
TEST(FxaaEdges, ScanFindsThePlainLoopsEdgesOnEveryInstructionSet) {
  std::mt19937 random(11);
  for (const int width : {3, 4, 17, 37, 64, 65, 66, 130, 203}) {
    for (const int kind : {0, 1, 2, 3}) {
      const int height = 3 + int(random() % 9);
      std::vector<std::uint8_t> luma(std::size_t(width) * height);
      for (std::size_t i = 0; i < luma.size(); ++i) {
        const int x = int(i % width);
        luma[i] = kind == 0   ? std::uint8_t(random() & 255)                        // noise
                  : kind == 1 ? std::uint8_t(x < width / 3 ? 40 : x < width - 2 ? 200 : 90)  // steps
                  : kind == 2 ? std::uint8_t(100 + (random() % 12))                  // near the threshold
                              : std::uint8_t(random() % 24);                         // dark: the least reduce
      }
      const std::uint8_t edge_min = 11;
      const FxaaEdges expected = plain_scan(luma, width, height, edge_min);
      luma.resize(luma.size() + fxaa_luma_padding(), 255);
      for (const std::int64_t target : hwy::SupportedAndGeneratedTargets()) {
        hwy::SetSupportedTargetsForTest(target);
        FxaaEdges edges;
        edges.push(0, 0, 1.0f, 1.0f, 0.0f, 1.0f);  // replaced by the scan
        std::vector<std::uint8_t> flags;
        fxaa_find_edges(luma.data(), width, height, edge_min, flags, edges);
        const std::string where = std::string(hwy::TargetName(target)) + ", width " +
                                  std::to_string(width) + ", kind " + std::to_string(kind);
        ASSERT_EQ(edges.size(), expected.size()) << where;
        const std::size_t n = expected.size();
        EXPECT_EQ(first(edges.x, n), first(expected.x, n)) << where;
        EXPECT_EQ(first(edges.y, n), first(expected.y, n)) << where;
        EXPECT_EQ(first(edges.dx, n), first(expected.dx, n)) << where;
        EXPECT_EQ(first(edges.dy, n), first(expected.dy, n)) << where;
        EXPECT_EQ(first(edges.luma_lo, n), first(expected.luma_lo, n)) << where;
        EXPECT_EQ(first(edges.luma_hi, n), first(expected.luma_hi, n)) << where;
      }
      hwy::SetSupportedTargetsForTest(0);
    }
  }
}

}  // namespace
}  // namespace tissu
