#include "text/font.h"

#include <stb_truetype.h>

#include <cstdlib>
#include <fstream>
#include <iterator>

#include "core/error.h"

#ifndef TISSU_FONT_FILE
#define TISSU_FONT_FILE "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf"
#endif

namespace tissu {

std::string default_font_file() {
  if (const char* path = std::getenv("TISSU_FONT_FILE")) return path;
  return TISSU_FONT_FILE;
}

TrueTypeFont::TrueTypeFont(const std::string& path)
    : path_(path), info_(std::make_unique<stbtt_fontinfo>()) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw OutputError(path + ": cannot read the font file");
  data_.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  // stb_truetype trusts its input: the file's signature is checked before it is opened.
  const int offset = data_.size() < 16 ? -1 : stbtt_GetFontOffsetForIndex(data_.data(), 0);
  if (offset < 0 || !stbtt_InitFont(info_.get(), data_.data(), offset)) {
    throw OutputError(path + ": not a TrueType font");
  }
}

TrueTypeFont::~TrueTypeFont() = default;

}  // namespace tissu
