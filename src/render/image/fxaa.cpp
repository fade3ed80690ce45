#include "render/image/fxaa.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "render/image/pixel_simd.h"

namespace tissu {

namespace {

constexpr float kSpanMax = 8.0f;            // pixels
constexpr float kReduceMul = 1.0f / 8.0f;
constexpr float kReduceMin = 1.0f / 128.0f;
constexpr float kEdgeMin = 1.0f / 24.0f;    // luma contrast, absolute
constexpr float kEdgeRelative = 1.0f / 8.0f;  // and relative to the brightest neighbour

struct Rgb {
  float r = 0, g = 0, b = 0;
};

float luma_of(const Rgb& c) { return (77.0f * c.r + 150.0f * c.g + 29.0f * c.b) * (1.0f / (256.0f * 255.0f)); }

// Bilinear sample of `src` at pixel coordinates (x, y) (pixel centres at integers),
// clamped to the image.
inline __attribute__((always_inline)) Rgb sample(const std::vector<std::uint8_t>& src, int width, int height,
                                                float x, float y) {
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

std::uint8_t to_byte(float v) { return static_cast<std::uint8_t>(std::clamp(v + 0.5f, 0.0f, 255.0f)); }

}  // namespace

void fxaa_rgb(std::vector<std::uint8_t>& rgb, int width, int height, FxaaScratch& scratch) {
  if (width < 3 || height < 3) return;
  const std::size_t n = std::size_t(width) * height;
  scratch.luma.resize(n);
  std::uint8_t* L = scratch.luma.data();
  rgb_luma(rgb.data(), L, n);  // Rec. 601 weights in 1/256ths: 77, 150, 29
  scratch.changed_at.clear();
  scratch.changed_rgb.clear();
  const std::uint8_t edge_min = static_cast<std::uint8_t>(std::lround(kEdgeMin * 255.0f));
  scratch.edge.resize(width);
  std::uint8_t* edge = scratch.edge.data();
  for (int y = 1; y + 1 < height; ++y) {
    const std::uint8_t* row = L + std::size_t(y) * width;
    const std::uint8_t* up = row - width;
    const std::uint8_t* down = row + width;
    // Which pixels of the row are on an edge: plain byte loops, which the compiler
    // vectorises (most pixels stop here).
    for (int x = 1; x + 1 < width; ++x) {
      const std::uint8_t hi = std::max(std::max(std::max(row[x], up[x]), std::max(down[x], row[x - 1])), row[x + 1]);
      const std::uint8_t lo = std::min(std::min(std::min(row[x], up[x]), std::min(down[x], row[x - 1])), row[x + 1]);
      const std::uint8_t threshold = std::max(edge_min, static_cast<std::uint8_t>(hi >> 3));  // kEdgeRelative
      edge[x] = static_cast<std::uint8_t>(hi - lo) >= threshold;
    }
    edge[0] = 0;
    edge[width - 1] = 0;
    for (int x = 1; x + 1 < width; ++x) {
      if (!edge[x]) {
        // Skip runs of flat pixels eight at a time (most of the frame).
        std::uint64_t eight;
        while (x + 9 < width && (std::memcpy(&eight, edge + x, 8), eight == 0)) x += 8;
        if (!edge[x]) continue;
      }
      const int m = row[x], w = row[x - 1], e = row[x + 1];
      const int hi = std::max({m, int(up[x]), int(down[x]), w, e});
      const int lo = std::min({m, int(up[x]), int(down[x]), w, e});
      // The four 2x2 blocks around the pixel, as the shader's half-pixel bilinear taps.
      constexpr float k = 1.0f / 255.0f;
      const float nw = 0.25f * k * (up[x - 1] + up[x] + w + m);
      const float ne = 0.25f * k * (up[x] + up[x + 1] + m + e);
      const float sw = 0.25f * k * (w + m + down[x - 1] + down[x]);
      const float se = 0.25f * k * (m + e + down[x] + down[x + 1]);
      const float block_lo =
          k * std::min({lo, int(up[x - 1]), int(up[x + 1]), int(down[x - 1]), int(down[x + 1])});
      const float block_hi =
          k * std::max({hi, int(up[x - 1]), int(up[x + 1]), int(down[x - 1]), int(down[x + 1])});
      // Across the luma gradient (gx, gy) is the edge's direction (gy, -gx); y grows down.
      float dx = (sw + se) - (nw + ne);
      float dy = (nw + sw) - (ne + se);
      const float reduce = std::max((nw + ne + sw + se) * 0.25f * kReduceMul, kReduceMin);
      const float scale = 1.0f / (std::min(std::fabs(dx), std::fabs(dy)) + reduce);
      dx = std::clamp(dx * scale, -kSpanMax, kSpanMax);
      dy = std::clamp(dy * scale, -kSpanMax, kSpanMax);
      const Rgb a = sample(rgb, width, height, x - dx / 6.0f, y - dy / 6.0f);
      const Rgb b = sample(rgb, width, height, x + dx / 6.0f, y + dy / 6.0f);
      const Rgb near{0.5f * (a.r + b.r), 0.5f * (a.g + b.g), 0.5f * (a.b + b.b)};
      const Rgb c = sample(rgb, width, height, x - dx * 0.5f, y - dy * 0.5f);
      const Rgb d = sample(rgb, width, height, x + dx * 0.5f, y + dy * 0.5f);
      const Rgb wide{0.5f * near.r + 0.25f * (c.r + d.r), 0.5f * near.g + 0.25f * (c.g + d.g),
                     0.5f * near.b + 0.25f * (c.b + d.b)};
      const float wide_luma = luma_of(wide);
      const Rgb& out = (wide_luma < block_lo || wide_luma > block_hi) ? near : wide;
      // Written after the scan: later pixels sample the frame as it was.
      scratch.changed_at.push_back(static_cast<std::uint32_t>(std::size_t(y) * width + x));
      scratch.changed_rgb.insert(scratch.changed_rgb.end(), {to_byte(out.r), to_byte(out.g), to_byte(out.b)});
    }
  }
  for (std::size_t k = 0; k < scratch.changed_at.size(); ++k) {
    std::copy_n(&scratch.changed_rgb[3 * k], 3, &rgb[3 * std::size_t(scratch.changed_at[k])]);
  }
}

}  // namespace tissu
