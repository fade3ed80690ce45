#include "render/draw/text_overlay.h"

#include <algorithm>
#include <cmath>

#include "text/font.h"

namespace tissu {

namespace {

struct TextVertex {
  float x, y, s, t;
};

const glm::vec4 kTextColor(0.97f, 0.97f, 0.97f, 1.0f);
const glm::vec4 kShadowColor(0.0f, 0.0f, 0.0f, 0.55f);

}  // namespace

TextOverlay::TextOverlay(const std::vector<std::string>& shader_dirs, int width, int height)
    : width_(width),
      height_(height),
      program_("text.vert", "text.frag", shader_dirs),
      vao_(make_vertex_array()),
      vertices_(make_buffer()) {
  glBindVertexArray(vao_.get());
  glBindBuffer(GL_ARRAY_BUFFER, vertices_.get());
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, sizeof(TextVertex), nullptr);
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 2, GL_FLOAT, GL_FALSE, sizeof(TextVertex),
                        reinterpret_cast<const void*>(2 * sizeof(float)));
  glBindVertexArray(0);
}

TextOverlay::Font& TextOverlay::font(std::unique_ptr<Font>& slot, float pixel_height) {
  if (slot) return *slot;
  slot = std::make_unique<Font>();
  slot->atlas = std::make_unique<FontAtlas>(default_font_file(), pixel_height);
  slot->texture = make_texture();
  const int size = slot->atlas->atlas_size();
  glBindTexture(GL_TEXTURE_2D, slot->texture.get());
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_R8, size, size, 0, GL_RED, GL_UNSIGNED_BYTE,
               slot->atlas->pixels().data());
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  check_gl("text overlay: uploading the font atlas");
  return *slot;
}

void TextOverlay::draw(const std::string& caption, const std::vector<std::string>& corner_lines) {
  if (caption.empty() && corner_lines.empty()) return;
  const float caption_px = std::clamp(std::round(height_ * 0.045f), 12.0f, 120.0f);
  const float corner_px = std::clamp(std::round(height_ * 0.035f), 11.0f, 80.0f);
  const float margin = std::round(std::max(4.0f, height_ * 0.025f));

  glDisable(GL_DEPTH_TEST);
  glDepthMask(GL_FALSE);
  glEnable(GL_BLEND);
  glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
  program_.use();
  program_.set("u_viewport", glm::vec2(width_, height_));
  program_.set("u_atlas", 0);

  if (!caption.empty()) {
    const Font& f = font(caption_font_, caption_px);
    std::vector<GlyphQuad> quads;
    float baseline = margin + f.atlas->ascent();
    for (const std::string& line : wrap_text(*f.atlas, caption, width_ - 2 * margin)) {
      const float x = std::round(0.5f * (width_ - f.atlas->width(line)));
      f.atlas->layout(line, x, std::round(baseline), &quads);
      baseline += f.atlas->line_height();
    }
    draw_quads(f, quads);
  }
  if (!corner_lines.empty()) {
    const Font& f = font(corner_font_, corner_px);
    std::vector<GlyphQuad> quads;
    // The last line sits one margin above the bottom edge.
    float baseline = height_ - margin - (f.atlas->line_height() - f.atlas->ascent()) -
                     f.atlas->line_height() * static_cast<float>(corner_lines.size() - 1);
    for (const std::string& line : corner_lines) {
      f.atlas->layout(line, margin, std::round(baseline), &quads);
      baseline += f.atlas->line_height();
    }
    draw_quads(f, quads);
  }
  glDisable(GL_BLEND);
  glDepthMask(GL_TRUE);
  glEnable(GL_DEPTH_TEST);
  check_gl("text overlay: drawing");
}

void TextOverlay::draw_quads(const Font& font, const std::vector<GlyphQuad>& quads) {
  std::vector<TextVertex> vertices;
  vertices.reserve(quads.size() * 6);
  for (const GlyphQuad& q : quads) {
    const TextVertex a{q.x0, q.y0, q.s0, q.t0}, b{q.x1, q.y0, q.s1, q.t0};
    const TextVertex c{q.x1, q.y1, q.s1, q.t1}, d{q.x0, q.y1, q.s0, q.t1};
    vertices.insert(vertices.end(), {a, b, c, a, c, d});
  }
  glBindBuffer(GL_ARRAY_BUFFER, vertices_.get());
  glBufferData(GL_ARRAY_BUFFER, vertices.size() * sizeof(TextVertex), vertices.data(),
               GL_STREAM_DRAW);
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_2D, font.texture.get());
  glBindVertexArray(vao_.get());
  const float shadow_offset = std::max(1.0f, std::round(height_ / 500.0f));
  const GLsizei count = static_cast<GLsizei>(vertices.size());
  program_.set("u_offset", glm::vec2(shadow_offset, shadow_offset));
  program_.set("u_color", kShadowColor);
  glDrawArrays(GL_TRIANGLES, 0, count);
  program_.set("u_offset", glm::vec2(0.0f));
  program_.set("u_color", kTextColor);
  glDrawArrays(GL_TRIANGLES, 0, count);
  glBindVertexArray(0);
}

}  // namespace tissu
