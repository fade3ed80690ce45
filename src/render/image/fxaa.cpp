#include "render/image/fxaa.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "render/image/fxaa_edges_simd.h"
#include "render/image/pixel_simd.h"

namespace tissu {

namespace {

constexpr float kSpanMax = 8.0f;            // pixels
constexpr float kReduceMul = 1.0f / 8.0f;
constexpr float kReduceMin = 1.0f / 128.0f;
constexpr float kEdgeMin = 1.0f / 24.0f;    // luma contrast, absolute
constexpr float kEdgeRelative = 1.0f / 8.0f;  // and relative to the brightest neighbour

}  // namespace

void fxaa_rgb(std::vector<std::uint8_t>& rgb, int width, int height, FxaaScratch& scratch) {
  if (width < 3 || height < 3) return;
  const std::size_t n = std::size_t(width) * height;
  scratch.luma.resize(n);
  std::uint8_t* L = scratch.luma.data();
  rgb_luma(rgb.data(), L, n);  // Rec. 601 weights in 1/256ths: 77, 150, 29
  FxaaEdges& edges = scratch.edges;
  edges.clear();
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
      // The samples along the edge are taken after the scan, several pixels at once, from
      // the frame as it was; the results are written after that.
      edges.x.push_back(x);
      edges.y.push_back(y);
      edges.dx.push_back(std::clamp(dx * scale, -kSpanMax, kSpanMax));
      edges.dy.push_back(std::clamp(dy * scale, -kSpanMax, kSpanMax));
      edges.luma_lo.push_back(block_lo);
      edges.luma_hi.push_back(block_hi);
    }
  }
  fxaa_blend_edges(rgb.data(), width, height, edges);
  for (std::size_t k = 0; k < edges.size(); ++k) {
    std::uint8_t* pixel = &rgb[3 * (std::size_t(edges.y[k]) * width + edges.x[k])];
    const std::uint32_t c = edges.blended[k];
    pixel[0] = static_cast<std::uint8_t>(c);
    pixel[1] = static_cast<std::uint8_t>(c >> 8);
    pixel[2] = static_cast<std::uint8_t>(c >> 16);
  }
}

}  // namespace tissu
