#include "text/text_bitmap.h"

#include <stb_truetype.h>

#include <algorithm>
#include <cmath>

#include "core/utf8.h"

namespace tissu {

TextBitmap BitmapFont::render(const std::string& text, double pixel_height) const {
  const stbtt_fontinfo& info = font_.info();
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
