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

// For each coverage 0..255, the blend out = color * alpha + out * (1 - alpha) with
// alpha = color.a * coverage / 255, in 16-bit fixed point: out = (add + out * keep) >> 16.
struct BlendTable {
  explicit BlendTable(const TextColor& color) {
    const float source[3] = {color.r * 255.0f, color.g * 255.0f, color.b * 255.0f};
    for (int cover = 0; cover < 256; ++cover) {
      const double alpha = color.a * (cover / 255.0);
      keep[cover] = static_cast<uint32_t>(std::lround((1.0 - alpha) * 65536.0));
      for (int c = 0; c < 3; ++c) {
        add[cover][c] = static_cast<uint32_t>(std::lround(source[c] * alpha * 65536.0)) + 32768;
      }
    }
  }
  uint32_t keep[256];
  uint32_t add[256][3];
};

const BlendTable kTextBlend(kTextColor);
const BlendTable kShadowBlend(kShadowColor);

// Blends the glyph cells of `quads`, shifted by `offset` pixels, with the atlas coverage
// as alpha, clipped to the image.
void blend_quads(const FontAtlas& font, const std::vector<GlyphQuad>& quads, int offset,
                 const BlendTable& table, int width, int height, std::vector<uint8_t>& rgb) {
  const int size = font.atlas_size();
  const std::vector<uint8_t>& atlas = font.pixels();
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
        const uint8_t k = cover[i];
        if (k == 0) continue;
        for (int c = 0; c < 3; ++c) {
          px[3 * i + c] = static_cast<uint8_t>((table.add[k][c] + px[3 * i + c] * table.keep[k]) >> 16);
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
    blend_quads(f, quads_, shadow_offset, kShadowBlend, width_, height_, rgb);
    blend_quads(f, quads_, 0, kTextBlend, width_, height_, rgb);
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
