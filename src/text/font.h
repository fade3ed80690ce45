// A TrueType font file read into memory and opened with stb_truetype: the one place the
// renderer's glyph atlas and the plots' text bitmaps get their fonts from.
#pragma once

#include <memory>
#include <string>
#include <vector>

struct stbtt_fontinfo;

namespace tissu {

// The font for captions, overlays and plots: $TISSU_FONT_FILE when set, else DejaVu Sans
// (found at configure time).
std::string default_font_file();

class TrueTypeFont {
 public:
  // Reads and opens `path`; throws OutputError naming the file when it cannot be read or
  // is not a TrueType font.
  explicit TrueTypeFont(const std::string& path);
  ~TrueTypeFont();
  TrueTypeFont(const TrueTypeFont&) = delete;
  TrueTypeFont& operator=(const TrueTypeFont&) = delete;

  const std::string& path() const { return path_; }
  const unsigned char* data() const { return data_.data(); }  // the file's bytes
  const stbtt_fontinfo& info() const { return *info_; }

 private:
  std::string path_;
  std::vector<unsigned char> data_;
  std::unique_ptr<stbtt_fontinfo> info_;
};

}  // namespace tissu
