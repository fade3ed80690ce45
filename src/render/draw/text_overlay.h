// Caption (centred at the top, word-wrapped) and corner lines (bottom left), drawn
// as anti-aliased glyph quads from font atlases baked once, with a soft drop shadow
// so the text reads on light and dark backgrounds alike.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "render/gl/gl_objects.h"
#include "render/gl/shader_program.h"
#include "text/font_atlas.h"

namespace tissu {

class TextOverlay {
 public:
  // Font sizes follow the image height. The font file is read at the first draw
  // that has text, so rendering without text never needs it.
  TextOverlay(const std::vector<std::string>& shader_dirs, int width, int height);

  // Draws into the bound framebuffer; blending is set and restored here.
  void draw(const std::string& caption, const std::vector<std::string>& corner_lines);

 private:
  struct Font {
    std::unique_ptr<FontAtlas> atlas;
    GlTexture texture;
  };
  Font& font(std::unique_ptr<Font>& slot, float pixel_height);
  void draw_quads(const Font& font, const std::vector<GlyphQuad>& quads);

  int width_, height_;
  ShaderProgram program_;
  GlVertexArray vao_;
  GlBuffer vertices_;
  std::unique_ptr<Font> caption_font_, corner_font_;
};

}  // namespace tissu
