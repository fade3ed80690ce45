// Composing a figure: panel pictures in a grid on a white page, a caption under each panel
// and the title under everything, in the manner of the paper's figures. Text is drawn on
// the CPU from the renderer's font atlas (DejaVu Sans, anti-aliased).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/types.h"
#include "text/font_atlas.h"
#include "video/image.h"

namespace tissu {

class TextPainter {
 public:
  // `pixel_height`: ascender-to-descender height. The font is the renderer's overlay font
  // (default_font_file()). Throws OutputError naming the file when it cannot be read.
  explicit TextPainter(float pixel_height);

  float width(const std::string& text) const;
  float line_height() const;
  float ascent() const;
  // Lines of `text` ("\n" breaks lines) word-wrapped to `max_width` pixels.
  std::vector<std::string> wrap(const std::string& text, float max_width) const;
  // Draws one line with its baseline at y, starting at x; colour in 0..1, blended by coverage.
  void draw(Image& image, const std::string& text, float x, float baseline, const Vec3& colour) const;

 private:
  std::unique_ptr<FontAtlas> atlas_;
};

struct FigureLayout {
  int columns = 1;
  int font_px = 0;  // caption text height; 0 = panel height / 22 (at least 11)
  std::string title;
};

// Panels must all have the same size. captions[i] may hold "\n" line breaks; lines are
// word-wrapped to the panel width and centred under the panel.
Image compose_figure(const std::vector<Image>& panels, const std::vector<std::string>& captions,
                     const FigureLayout& layout);

}  // namespace tissu
