#include "render/image/fxaa.h"

#include <cmath>

#include "render/image/fxaa_edges_simd.h"
#include "render/image/pixel_simd.h"

namespace tissu {

namespace {

constexpr float kEdgeMin = 1.0f / 24.0f;  // luma contrast, absolute (and 1/8 of the brightest)

}  // namespace

void fxaa_rgb(std::vector<std::uint8_t>& rgb, int width, int height, FxaaScratch& scratch) {
  if (width < 3 || height < 3) return;
  const std::size_t n = std::size_t(width) * height;
  scratch.luma.resize(n + fxaa_luma_padding());
  rgb_luma(rgb.data(), scratch.luma.data(), n);  // Rec. 601 weights in 1/256ths: 77, 150, 29
  const std::uint8_t edge_min = static_cast<std::uint8_t>(std::lround(kEdgeMin * 255.0f));
  FxaaEdges& edges = scratch.edges;
  fxaa_find_edges(scratch.luma.data(), width, height, edge_min, scratch.edge, edges);
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
