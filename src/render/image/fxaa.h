// FXAA on the processor: fast approximate anti-aliasing of a single-sample RGB frame after
// it was read back (after Lottes' FXAA "console" variant). On llvmpipe a full-screen
// filter pass costs 30-40 ms of processor time per 1280x720 frame, nine texture reads per
// pixel; here only pixels on an edge do more than read five lumas: a few ms.
#pragma once

#include <cstdint>
#include <vector>

#include "render/image/fxaa_edges_simd.h"

namespace tissu {

struct FxaaScratch {
  std::vector<std::uint8_t> luma;  // per pixel, 0..255 (and padding for the scan)
  std::vector<std::uint8_t> edge;  // the scan's flags per pixel of a row (and padding)
  FxaaEdges edges;  // the pixels on an edge, and their new colours
};

// Smooths the edges of `rgb` (width * height * 3 bytes, rows in any order) in place. A
// pixel whose four direct neighbours differ from it by less than a luma contrast of
// max(1/24, 1/8 of the brightest) is left exactly as it is; elsewhere the local luma
// gradient gives the edge's direction, and the pixel becomes the mean of two (or, unless
// that brings in a luma outside its 3x3 neighbourhood, four) bilinear samples along it, at
// most 8 pixels away. Border pixels are left as they are.
void fxaa_rgb(std::vector<std::uint8_t>& rgb, int width, int height, FxaaScratch& scratch);

}  // namespace tissu
