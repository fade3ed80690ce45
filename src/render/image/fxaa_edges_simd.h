// FXAA's scan for edge pixels and its work on them (render/image/fxaa.h) in SIMD, several
// pixels at once (Google Highway, the instruction set chosen at run time). The float steps
// are those of the plain per-pixel loop, in its order and without fused multiply-adds, so
// the edges found and the bytes written are the same on every instruction set of x86 and
// 64-bit Arm (where division is exact; 32-bit Arm NEON only estimates it).
#pragma once

#include <cstdint>
#include <vector>

namespace tissu {

// Edge pixels found by FXAA's scan: the first `count` entries of each array, one per
// pixel (the arrays keep their length from frame to frame, so they are not refilled).
struct FxaaEdges {
  std::vector<std::int32_t> x, y;          // pixel, inside the image's border
  std::vector<float> dx, dy;               // span along the edge, pixels, within +-8
  std::vector<float> luma_lo, luma_hi;     // luma range of the 3x3 block, 0..1
  std::vector<std::uint32_t> blended;      // out: r | g << 8 | b << 16
  std::size_t count = 0;

  void clear() { count = 0; }
  std::size_t size() const { return count; }
  // Lengthens the arrays, if needed, to hold `more` entries after the first `count` (the
  // scan stores whole vectors).
  void make_room(std::size_t more);
  // Appends one pixel (tests and callers outside the scan).
  void push(std::int32_t px, std::int32_t py, float span_x, float span_y, float lo, float hi);
};

// Bytes of padding `luma` needs after its width * height pixels for fxaa_find_edges.
std::size_t fxaa_luma_padding();

// The scan: every pixel inside the image's border where the luma (`luma`: 0..255, width *
// height, then fxaa_luma_padding() bytes of any value) of the pixel and its four direct
// neighbours spans at least max(edge_min, 1/8 of the brightest of the five), in rows top
// to bottom and each from left to right, with its span along the edge and its 3x3 block's
// luma range. `row_flags` is scratch. Replaces edges' content.
void fxaa_find_edges(const std::uint8_t* luma, int width, int height, std::uint8_t edge_min,
                     std::vector<std::uint8_t>& row_flags, FxaaEdges& edges);

// For every edge pixel: two bilinear samples of `rgb` (width * height * 3 bytes) at 1/6
// of the span on either side and two at 1/2; the mean of the near two, or, when its luma
// stays within the pixel's luma range, half of it plus a quarter of each far one.
// Sample points are clamped to the image. Fills edges.blended.
void fxaa_blend_edges(const std::uint8_t* rgb, int width, int height, FxaaEdges& edges);

}  // namespace tissu
