// Text rasterized on the processor into a coverage bitmap, for plots and images drawn
// without the renderer.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "text/font.h"

namespace tissu {

// Coverage (0-255) of a line of text, row by row from the top.
struct TextBitmap {
  int width = 0;
  int height = 0;
  int baseline = 0;  // rows from the top to the baseline
  std::vector<std::uint8_t> coverage;
};

class BitmapFont {
 public:
  // Loads a .ttf file; throws OutputError naming the file when it cannot be read or parsed.
  explicit BitmapFont(const std::string& ttf_file) : font_(ttf_file) {}

  // Renders UTF-8 `text` with letters `pixel_height` pixels tall (ascent to descent).
  TextBitmap render(const std::string& text, double pixel_height) const;

 private:
  TrueTypeFont font_;
};

}  // namespace tissu
