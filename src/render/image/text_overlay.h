// Caption (centred at the top, word-wrapped) and corner lines (bottom left), blended
// into the read-back RGB image on the processor from font atlases baked once, with a
// soft drop shadow so the text reads on light and dark backgrounds alike. Glyphs sit on
// whole pixels and the atlas is baked at the drawn size, so each glyph is a copy of its
// atlas cells: no resampling, and a few thousand pixels a frame instead of a GL pass.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "text/font_atlas.h"

namespace tissu {

class TextOverlay {
 public:
  // Font sizes follow the image height. The font file is read at the first frame that
  // has text, so rendering without text never needs it.
  TextOverlay(int width, int height);
  ~TextOverlay();

  // Blends the text into `rgb` (width * height * 3 bytes, first row at the top).
  void blend(const std::string& caption, const std::vector<std::string>& corner_lines,
             std::vector<uint8_t>& rgb);

 private:
  const FontAtlas& font(std::unique_ptr<FontAtlas>& slot, float pixel_height);

  int width_, height_;
  std::unique_ptr<FontAtlas> caption_font_, corner_font_;
  std::vector<GlyphQuad> quads_;  // reused between frames
};

}  // namespace tissu
