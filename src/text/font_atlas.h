// Glyph bitmaps of one TrueType font at one pixel size, baked once into an
// 8-bit coverage atlas (stb_truetype), and the layout of text lines as quads.
// Covers Latin-1 and Greek; other characters are drawn as '?'.
#pragma once

#include "core/utf8.h"  // decode_utf8

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace tissu {

struct GlyphQuad {
  float x0, y0, x1, y1;  // pixels, y down
  float s0, t0, s1, t1;  // atlas coordinates (0..1)
};

class FontAtlas {
 public:
  // `pixel_height`: ascender-to-descender height in pixels. Throws OutputError
  // naming the file when it cannot be read or is not a TrueType font.
  FontAtlas(const std::string& ttf_path, float pixel_height);
  ~FontAtlas();
  FontAtlas(const FontAtlas&) = delete;
  FontAtlas& operator=(const FontAtlas&) = delete;

  // Appends the quads of UTF-8 `text` with its baseline starting at (x, baseline);
  // returns the x after the last glyph. `quads` may be null to measure only.
  float layout(const std::string& text, float x, float baseline,
               std::vector<GlyphQuad>* quads) const;
  float width(const std::string& text) const { return layout(text, 0, 0, nullptr); }

  float ascent() const { return ascent_; }        // pixels above the baseline
  float line_height() const { return line_height_; }
  int atlas_size() const { return atlas_size_; }  // the atlas is square
  const std::vector<uint8_t>& pixels() const { return pixels_; }

 private:
  struct Glyphs;
  std::unique_ptr<Glyphs> glyphs_;
  int atlas_size_ = 0;
  std::vector<uint8_t> pixels_;
  float ascent_ = 0, line_height_ = 0;
};


// Greedy word wrap of `text` into lines no wider than `max_width` pixels.
std::vector<std::string> wrap_text(const FontAtlas& font, const std::string& text,
                                   float max_width);

}  // namespace tissu
