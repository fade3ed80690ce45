// Text for plots: a TrueType font rasterized with stb_truetype.
//
// src/render/font_atlas.cpp links stb_truetype's implementation with external symbols into
// tissu_render. The study module must not depend on the renderer, and two external copies
// in one program would clash, so plot_font.cpp compiles its own copy with
// STBTT_STATIC: every stb function gets internal linkage in that one object file.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace tissu {

// Coverage (0-255) of a line of text, row by row from the top.
struct TextBitmap {
  int width = 0;
  int height = 0;
  int baseline = 0;  // rows from the top to the baseline
  std::vector<std::uint8_t> coverage;
};

class PlotFont {
 public:
  // Loads a .ttf file; throws OutputError naming the file when it cannot be read or parsed.
  explicit PlotFont(const std::string& ttf_file);
  ~PlotFont();
  PlotFont(const PlotFont&) = delete;
  PlotFont& operator=(const PlotFont&) = delete;

  // Renders UTF-8 `text` with letters `pixel_height` pixels tall (ascent to descent).
  TextBitmap render(const std::string& text, double pixel_height) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// The font plots use: DejaVu Sans (found at configure time).
std::string default_plot_font_file();

}  // namespace tissu
