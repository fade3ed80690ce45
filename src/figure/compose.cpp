#include "figure/compose.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "text/font.h"

namespace tissu {

namespace {

const Vec3 kPage(1.0, 1.0, 1.0);
const Vec3 kText(0.08, 0.08, 0.08);
const Vec3 kFrame(0.55, 0.55, 0.55);

void fill(Image& image, int x0, int y0, int w, int h, const Vec3& colour) {
  const uint8_t c[3] = {static_cast<uint8_t>(std::lround(255 * colour.x())),
                        static_cast<uint8_t>(std::lround(255 * colour.y())),
                        static_cast<uint8_t>(std::lround(255 * colour.z()))};
  for (int y = std::max(0, y0); y < std::min(image.height, y0 + h); ++y) {
    for (int x = std::max(0, x0); x < std::min(image.width, x0 + w); ++x) {
      uint8_t* p = image.pixel(x, y);
      p[0] = c[0];
      p[1] = c[1];
      p[2] = c[2];
    }
  }
}

void blit(Image& page, const Image& panel, int x0, int y0) {
  for (int y = 0; y < panel.height; ++y) {
    std::copy_n(panel.pixel(0, y), 3 * panel.width, page.pixel(x0, y0 + y));
  }
}

}  // namespace

TextPainter::TextPainter(float pixel_height)
    : atlas_(std::make_unique<FontAtlas>(default_font_file(), pixel_height)) {}

float TextPainter::width(const std::string& text) const { return atlas_->width(text); }
float TextPainter::line_height() const { return atlas_->line_height(); }
float TextPainter::ascent() const { return atlas_->ascent(); }

std::vector<std::string> TextPainter::wrap(const std::string& text, float max_width) const {
  return wrap_text(*atlas_, text, max_width);
}

void TextPainter::draw(Image& image, const std::string& text, float x, float baseline,
                       const Vec3& colour) const {
  std::vector<GlyphQuad> quads;
  atlas_->layout(text, std::round(x), std::round(baseline), &quads);
  const int size = atlas_->atlas_size();
  const std::vector<uint8_t>& coverage = atlas_->pixels();
  for (const GlyphQuad& q : quads) {
    // Quads are pixel aligned and glyphs baked at their drawn size: one atlas texel per pixel.
    const int x0 = static_cast<int>(std::lround(q.x0)), y0 = static_cast<int>(std::lround(q.y0));
    const int w = static_cast<int>(std::lround(q.x1 - q.x0));
    const int h = static_cast<int>(std::lround(q.y1 - q.y0));
    const int s0 = static_cast<int>(std::lround(q.s0 * size));
    const int t0 = static_cast<int>(std::lround(q.t0 * size));
    for (int j = 0; j < h; ++j) {
      const int y = y0 + j;
      if (y < 0 || y >= image.height || t0 + j >= size) continue;
      for (int i = 0; i < w; ++i) {
        const int px = x0 + i;
        if (px < 0 || px >= image.width || s0 + i >= size) continue;
        const double a = coverage[static_cast<size_t>(t0 + j) * size + (s0 + i)] / 255.0;
        if (a <= 0.0) continue;
        uint8_t* p = image.pixel(px, y);
        for (int c = 0; c < 3; ++c) {
          p[c] = static_cast<uint8_t>(std::lround((1.0 - a) * p[c] + a * 255.0 * colour[c]));
        }
      }
    }
  }
}

Image compose_figure(const std::vector<Image>& panels, const std::vector<std::string>& captions,
                     const FigureLayout& layout) {
  if (panels.empty()) throw std::invalid_argument("compose_figure: no panels");
  if (captions.size() != panels.size()) {
    throw std::invalid_argument("compose_figure: one caption per panel expected");
  }
  const int pw = panels[0].width, ph = panels[0].height;
  for (const Image& p : panels) {
    if (p.width != pw || p.height != ph) {
      throw std::invalid_argument("compose_figure: panels differ in size");
    }
  }
  const int columns = std::clamp(layout.columns, 1, static_cast<int>(panels.size()));
  const int rows = (static_cast<int>(panels.size()) + columns - 1) / columns;
  const int font_px = layout.font_px > 0 ? layout.font_px : std::max(11, ph / 22);
  const TextPainter caption_font(static_cast<float>(font_px));
  const TextPainter title_font(std::round(font_px * 1.2f));
  const int margin = std::max(8, font_px);
  const int gap = std::max(6, font_px / 2);  // between a panel and its caption
  const int line = static_cast<int>(std::ceil(caption_font.line_height()));

  std::vector<std::vector<std::string>> lines;
  size_t most = 0;
  for (const std::string& c : captions) {
    lines.push_back(caption_font.wrap(c, static_cast<float>(pw)));
    while (!lines.back().empty() && lines.back().back().empty()) lines.back().pop_back();
    most = std::max(most, lines.back().size());
  }
  const int caption_h = static_cast<int>(most) * line;
  const int cell_w = pw, cell_h = ph + gap + caption_h;
  const int width_raw = 2 * margin + columns * cell_w + (columns - 1) * margin;
  const std::vector<std::string> title_lines =
      layout.title.empty() ? std::vector<std::string>{}
                           : title_font.wrap(layout.title, static_cast<float>(width_raw - 2 * margin));
  const int title_line = static_cast<int>(std::ceil(title_font.line_height()));
  const int title_h = title_lines.empty() ? 0 : margin / 2 + static_cast<int>(title_lines.size()) * title_line;
  int width = width_raw, height = 2 * margin + rows * cell_h + (rows - 1) * margin + title_h;
  width += width % 2;  // even sizes suit video encoders and half-size previews
  height += height % 2;

  Image page(width, height);
  fill(page, 0, 0, width, height, kPage);
  for (size_t i = 0; i < panels.size(); ++i) {
    const int col = static_cast<int>(i) % columns, row = static_cast<int>(i) / columns;
    const int x0 = margin + col * (cell_w + margin);
    const int y0 = margin + row * (cell_h + margin);
    fill(page, x0 - 1, y0 - 1, pw + 2, ph + 2, kFrame);
    blit(page, panels[i], x0, y0);
    float baseline = static_cast<float>(y0 + ph + gap) + caption_font.ascent();
    for (const std::string& text : lines[i]) {
      const float x = static_cast<float>(x0) + 0.5f * (pw - caption_font.width(text));
      caption_font.draw(page, text, x, baseline, kText);
      baseline += static_cast<float>(line);
    }
  }
  float baseline = static_cast<float>(height - margin - title_h + margin / 2) + title_font.ascent();
  for (const std::string& text : title_lines) {
    const float x = 0.5f * (static_cast<float>(width) - title_font.width(text));
    title_font.draw(page, text, x, baseline, kText);
    baseline += static_cast<float>(title_line);
  }
  return page;
}

}  // namespace tissu
