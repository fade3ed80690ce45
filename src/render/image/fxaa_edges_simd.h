// FXAA's work on the pixels of an edge (render/image/fxaa.h) in SIMD, several edge pixels
// at once (Google Highway, the instruction set chosen at run time). The float steps are
// those of the plain per-pixel loop, in its order and without fused multiply-adds, so the
// bytes are the same on every instruction set.
#pragma once

#include <cstdint>
#include <vector>

namespace tissu {

// Edge pixels found by FXAA's scan, one entry per pixel in each array (same length).
struct FxaaEdges {
  std::vector<std::int32_t> x, y;          // pixel, inside the image's border
  std::vector<float> dx, dy;               // span along the edge, pixels, within +-8
  std::vector<float> luma_lo, luma_hi;     // luma range of the 3x3 block, 0..1
  std::vector<std::uint32_t> blended;      // out: r | g << 8 | b << 16

  void clear();
  std::size_t size() const { return x.size(); }
};

// For every edge pixel: two bilinear samples of `rgb` (width * height * 3 bytes) at 1/6
// of the span on either side and two at 1/2; the mean of the near two, or, when its luma
// stays within the pixel's luma range, half of it plus a quarter of each far one.
// Sample points are clamped to the image. Fills edges.blended.
void fxaa_blend_edges(const std::uint8_t* rgb, int width, int height, FxaaEdges& edges);

}  // namespace tissu
