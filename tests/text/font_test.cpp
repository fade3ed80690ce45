// The text module: one font file reading for the renderer's glyph atlas and the plots'
// text bitmaps, UTF-8 decoding, layout and word wrap.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "core/error.h"
#include "core/utf8.h"
#include "text/font.h"
#include "text/font_atlas.h"
#include "text/text_bitmap.h"

namespace tissu {
namespace {

TEST(Text, DecodesUtf8) {
  EXPECT_EQ(decode_utf8("a\xC3\xA9\xCE\x94"), (std::vector<uint32_t>{'a', 0xE9, 0x394}));
  EXPECT_EQ(decode_utf8("\xFF" "b"), (std::vector<uint32_t>{0xFFFD, 'b'}));
}

TEST(Text, AtlasLayoutAndWrapping) {
  const FontAtlas font(default_font_file(), 20.0f);
  EXPECT_GT(font.width("WWW"), font.width("iii"));
  std::vector<GlyphQuad> quads;
  font.layout("A b", 10, 30, &quads);
  EXPECT_EQ(quads.size(), 2u);  // the space has no quad
  EXPECT_LT(quads[0].y0, 30.0f);  // glyphs rise above the baseline (y down)
  const std::vector<std::string> lines =
      wrap_text(font, "one two three four five six seven", font.width("one two three"));
  ASSERT_GE(lines.size(), 3u);
  EXPECT_EQ(lines[0], "one two three");
  for (const std::string& line : lines) EXPECT_LE(font.width(line), font.width("one two three"));
}

// The atlas and the bitmaps agree on the font's size: a line of text measured by both
// differs by less than two pixels.
TEST(Text, AtlasAndBitmapMeasureAlike) {
  const std::string line = "Tissu: cotton 5000 triangles";
  const FontAtlas atlas(default_font_file(), 20.0f);
  const TextBitmap bitmap = BitmapFont(default_font_file()).render(line, 20.0);
  EXPECT_NEAR(bitmap.width - 3, atlas.width(line), 2.0);  // the bitmap pads 1 + 2 pixels
  EXPECT_NEAR(bitmap.height, atlas.line_height(), 3.0);
}

TEST(Text, MissingFontIsAnOutputErrorNamingTheFile) {
  for (int user = 0; user < 2; ++user) {
    try {
      if (user == 0) FontAtlas("/nonexistent/font.ttf", 12.0f);
      if (user == 1) BitmapFont("/nonexistent/font.ttf");
      FAIL() << "no error";
    } catch (const OutputError& e) {
      EXPECT_STREQ(e.what(), "/nonexistent/font.ttf: cannot read the font file");
    }
  }
}

TEST(Text, FileThatIsNotAFontIsNamed) {
  const std::string path = std::string(TISSU_SOURCE_DIR) + "/README.md";
  try {
    TrueTypeFont font(path);
    FAIL() << "no error";
  } catch (const OutputError& e) {
    EXPECT_EQ(std::string(e.what()), path + ": not a TrueType font");
  }
}

}  // namespace
}  // namespace tissu
