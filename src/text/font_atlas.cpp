#include "text/font_atlas.h"

#include <stb_truetype.h>

#include <cmath>

#include "core/error.h"
#include "text/font.h"

namespace tissu {

namespace {

struct CodeRange {
  int first, count;
};
// Latin-1 (printable ASCII and accented letters) and Greek.
constexpr CodeRange kRanges[] = {{32, 95}, {160, 96}, {0x391, 0x3C9 - 0x391 + 1}};

}  // namespace

struct FontAtlas::Glyphs {
  std::vector<std::vector<stbtt_packedchar>> ranges;  // one list per kRanges entry
};

FontAtlas::FontAtlas(const std::string& ttf_path, float pixel_height)
    : glyphs_(std::make_unique<Glyphs>()) {
  const TrueTypeFont font(ttf_path);
  const stbtt_fontinfo& info = font.info();
  int ascent = 0, descent = 0, gap = 0;
  stbtt_GetFontVMetrics(&info, &ascent, &descent, &gap);
  const float scale = stbtt_ScaleForPixelHeight(&info, pixel_height);
  ascent_ = ascent * scale;
  line_height_ = (ascent - descent + gap) * scale;

  // Grow the atlas until every glyph fits (about 350 glyphs).
  for (atlas_size_ = 256;; atlas_size_ *= 2) {
    pixels_.assign(static_cast<size_t>(atlas_size_) * atlas_size_, 0);
    std::vector<stbtt_pack_range> ranges;
    glyphs_->ranges.clear();
    for (const CodeRange& r : kRanges) glyphs_->ranges.emplace_back(r.count);
    for (size_t i = 0; i < std::size(kRanges); ++i) {
      stbtt_pack_range range{};
      range.font_size = pixel_height;
      range.first_unicode_codepoint_in_range = kRanges[i].first;
      range.num_chars = kRanges[i].count;
      range.chardata_for_range = glyphs_->ranges[i].data();
      ranges.push_back(range);
    }
    stbtt_pack_context pack;
    if (!stbtt_PackBegin(&pack, pixels_.data(), atlas_size_, atlas_size_, 0, 1, nullptr)) {
      throw OutputError(ttf_path + ": cannot start packing the font atlas");
    }
    const int packed = stbtt_PackFontRanges(&pack, font.data(), 0, ranges.data(),
                                            static_cast<int>(ranges.size()));
    stbtt_PackEnd(&pack);
    if (packed) break;
    if (atlas_size_ >= 8192) {
      throw OutputError(ttf_path + ": glyphs of " + std::to_string(pixel_height) +
                        " px do not fit an 8192 px atlas");
    }
  }
}

FontAtlas::~FontAtlas() = default;

float FontAtlas::layout(const std::string& text, float x, float baseline,
                        std::vector<GlyphQuad>* quads) const {
  for (uint32_t code : decode_utf8(text)) {
    const stbtt_packedchar* glyphs = nullptr;
    int index = 0;
    for (size_t i = 0; i < std::size(kRanges) && glyphs == nullptr; ++i) {
      const int offset = static_cast<int>(code) - kRanges[i].first;
      if (offset >= 0 && offset < kRanges[i].count) {
        glyphs = glyphs_->ranges[i].data();
        index = offset;
      }
    }
    if (glyphs == nullptr) {  // not in the atlas
      glyphs = glyphs_->ranges[0].data();
      index = '?' - kRanges[0].first;
    }
    stbtt_aligned_quad q;
    float y = baseline;
    stbtt_GetPackedQuad(glyphs, atlas_size_, atlas_size_, index, &x, &y, &q, 1);
    if (quads != nullptr && q.x1 > q.x0) {
      quads->push_back({q.x0, q.y0, q.x1, q.y1, q.s0, q.t0, q.s1, q.t1});
    }
  }
  return x;
}

std::vector<std::string> wrap_text(const FontAtlas& font, const std::string& text,
                                   float max_width) {
  std::vector<std::string> lines;
  std::string line, word;
  auto flush_word = [&]() {
    if (word.empty()) return;
    const std::string joined = line.empty() ? word : line + " " + word;
    if (!line.empty() && font.width(joined) > max_width) {
      lines.push_back(line);
      line = word;
    } else {
      line = joined;
    }
    word.clear();
  };
  for (char c : text) {
    if (c == ' ' || c == '\n') {
      flush_word();
      if (c == '\n') {
        lines.push_back(line);
        line.clear();
      }
    } else {
      word += c;
    }
  }
  flush_word();
  if (!line.empty() || lines.empty()) lines.push_back(line);
  return lines;
}

}  // namespace tissu
