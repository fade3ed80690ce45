#include "render/image/text_overlay.h"

#include <algorithm>
#include <cmath>

#include "text/font.h"

namespace tissu {

namespace {

struct TextColor {
  float r, g, b, a;  // 0..1
};

const TextColor kTextColor{0.97f, 0.97f, 0.97f, 1.0f};
const TextColor kShadowColor{0.0f, 0.0f, 0.0f, 0.55f};

// Blends the glyph cells of `quads`, shifted by `offset` pixels, in `color` with the
// atlas coverage as alpha: out = color * alpha + out * (1 - alpha), clipped to the image.
void blend_quads(const FontAtlas& font, const std::vector<GlyphQuad>& quads, int offset,
                 const TextColor& color, int width, int height, std::vector<uint8_t>& rgb) {
  const int size = font.atlas_size();
  const std::vector<uint8_t>& atlas = font.pixels();
  const float source[3] = {color.r * 255.0f, color.g * 255.0f, color.b * 255.0f};
  for (const GlyphQuad& q : quads) {
    const int x0 = static_cast<int>(std::lround(q.x0)) + offset;
    const int y0 = static_cast<int>(std::lround(q.y0)) + offset;
    const int s0 = static_cast<int>(std::lround(q.s0 * size));
    const int t0 = static_cast<int>(std::lround(q.t0 * size));
    const int w = static_cast<int>(std::lround(q.x1 - q.x0));
    const int h = static_cast<int>(std::lround(q.y1 - q.y0));
    for (int j = std::max(0, -y0); j < h && y0 + j < height; ++j) {
      const uint8_t* cover = atlas.data() + static_cast<size_t>(t0 + j) * size + s0;
      uint8_t* px = rgb.data() + (static_cast<size_t>(y0 + j) * width + x0) * 3;
      for (int i = std::max(0, -x0); i < w && x0 + i < width; ++i) {
        if (cover[i] == 0) continue;
        const float alpha = color.a * (cover[i] / 255.0f);
        for (int c = 0; c < 3; ++c) {
          const float v = source[c] * alpha + px[3 * i + c] * (1.0f - alpha);
          px[3 * i + c] = static_cast<uint8_t>(std::lround(v));
        }
      }
    }
  }
}

}  // namespace

TextOverlay::TextOverlay(int width, int height) : width_(width), height_(height) {}
TextOverlay::~TextOverlay() = default;

const FontAtlas& TextOverlay::font(std::unique_ptr<FontAtlas>& slot, float pixel_height) {
  if (!slot) slot = std::make_unique<FontAtlas>(default_font_file(), pixel_height);
  return *slot;
}

void TextOverlay::blend(const std::string& caption, const std::vector<std::string>& corner_lines,
                        std::vector<uint8_t>& rgb) {
  if (caption.empty() && corner_lines.empty()) return;
  const float caption_px = std::clamp(std::round(height_ * 0.045f), 12.0f, 120.0f);
  const float corner_px = std::clamp(std::round(height_ * 0.035f), 11.0f, 80.0f);
  const float margin = std::round(std::max(4.0f, height_ * 0.025f));
  const int shadow_offset = static_cast<int>(std::max(1.0f, std::round(height_ / 500.0f)));
  auto blend_with_shadow = [&](const FontAtlas& f) {
    blend_quads(f, quads_, shadow_offset, kShadowColor, width_, height_, rgb);
    blend_quads(f, quads_, 0, kTextColor, width_, height_, rgb);
  };

  if (!caption.empty()) {
    const FontAtlas& f = font(caption_font_, caption_px);
    quads_.clear();
    float baseline = margin + f.ascent();
    for (const std::string& line : wrap_text(f, caption, width_ - 2 * margin)) {
      const float x = std::round(0.5f * (width_ - f.width(line)));
      f.layout(line, x, std::round(baseline), &quads_);
      baseline += f.line_height();
    }
    blend_with_shadow(f);
  }
  if (!corner_lines.empty()) {
    const FontAtlas& f = font(corner_font_, corner_px);
    quads_.clear();
    // The last line sits one margin above the bottom edge.
    float baseline = height_ - margin - (f.line_height() - f.ascent()) -
                     f.line_height() * static_cast<float>(corner_lines.size() - 1);
    for (const std::string& line : corner_lines) {
      f.layout(line, margin, std::round(baseline), &quads_);
      baseline += f.line_height();
    }
    blend_with_shadow(f);
  }
}

}  // namespace tissu
