// stb_truetype with internal linkage (see plot_font.h), compiled without warnings.
#define STBTT_STATIC
#define STB_TRUETYPE_IMPLEMENTATION
#include <stb_truetype.h>

#include "study/plot_font.h"

#include <cmath>
#include <fstream>
#include <iterator>

#include "core/error.h"
#include "core/utf8.h"

#ifndef TISSU_PLOT_FONT_FILE
#define TISSU_PLOT_FONT_FILE "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf"
#endif

namespace tissu {

struct PlotFont::Impl {
  std::vector<unsigned char> data;
  stbtt_fontinfo info{};
};

std::string default_plot_font_file() { return TISSU_PLOT_FONT_FILE; }

PlotFont::PlotFont(const std::string& ttf_file) : impl_(std::make_unique<Impl>()) {
  std::ifstream in(ttf_file, std::ios::binary);
  if (!in) throw OutputError(ttf_file + ": cannot read the plot font");
  impl_->data.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  if (impl_->data.empty() ||
      !stbtt_InitFont(&impl_->info, impl_->data.data(),
                      stbtt_GetFontOffsetForIndex(impl_->data.data(), 0))) {
    throw OutputError(ttf_file + ": not a TrueType font");
  }
}

PlotFont::~PlotFont() = default;

TextBitmap PlotFont::render(const std::string& text, double pixel_height) const {
  const stbtt_fontinfo& info = impl_->info;
  const float scale = stbtt_ScaleForPixelHeight(&info, static_cast<float>(pixel_height));
  int ascent = 0, descent = 0, gap = 0;
  stbtt_GetFontVMetrics(&info, &ascent, &descent, &gap);
  const int baseline = static_cast<int>(std::ceil(ascent * scale));
  const int height = baseline + static_cast<int>(std::ceil(-descent * scale)) + 1;
  const std::vector<uint32_t> cps = decode_utf8(text);

  // Pen positions first, to size the bitmap.
  std::vector<float> pen(cps.size());
  float x = 1.0f;
  for (size_t i = 0; i < cps.size(); ++i) {
    pen[i] = x;
    int advance = 0, bearing = 0;
    stbtt_GetCodepointHMetrics(&info, cps[i], &advance, &bearing);
    x += advance * scale;
    if (i + 1 < cps.size()) x += scale * stbtt_GetCodepointKernAdvance(&info, cps[i], cps[i + 1]);
  }
  TextBitmap bm;
  bm.width = static_cast<int>(std::ceil(x)) + 2;
  bm.height = height;
  bm.baseline = baseline;
  bm.coverage.assign(static_cast<size_t>(bm.width) * bm.height, 0);

  // Each glyph rendered at its sub-pixel pen position, combined with max().
  for (size_t i = 0; i < cps.size(); ++i) {
    const float shift = pen[i] - std::floor(pen[i]);
    int x0, y0, x1, y1;
    stbtt_GetCodepointBitmapBoxSubpixel(&info, cps[i], scale, scale, shift, 0.0f, &x0, &y0, &x1,
                                        &y1);
    const int w = x1 - x0, h = y1 - y0;
    if (w <= 0 || h <= 0) continue;
    std::vector<unsigned char> glyph(static_cast<size_t>(w) * h);
    stbtt_MakeCodepointBitmapSubpixel(&info, glyph.data(), w, h, w, scale, scale, shift, 0.0f,
                                      cps[i]);
    const int ox = static_cast<int>(std::floor(pen[i])) + x0, oy = baseline + y0;
    for (int gy = 0; gy < h; ++gy) {
      for (int gx = 0; gx < w; ++gx) {
        const int px = ox + gx, py = oy + gy;
        if (px < 0 || py < 0 || px >= bm.width || py >= bm.height) continue;
        std::uint8_t& c = bm.coverage[static_cast<size_t>(py) * bm.width + px];
        c = std::max<std::uint8_t>(c, glyph[static_cast<size_t>(gy) * w + gx]);
      }
    }
  }
  return bm;
}

}  // namespace tissu
