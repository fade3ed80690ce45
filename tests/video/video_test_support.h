// Helpers for the video tests: synthetic frames, scratch directories and an independent
// reader of MP4 files built directly on libavformat/libavcodec.
#pragma once

#include <string>
#include <vector>

#include "video/image.h"

namespace tissu::test {

// A colourful diagonal gradient that moves by `index` pixels per frame.
Image moving_gradient(int width, int height, int index);

// Pseudo-random pixels (hard to compress), the same for the same seed.
Image noise_image(int width, int height, unsigned seed);

// A fresh empty directory, removed with its contents on destruction.
class ScratchDir {
 public:
  ScratchDir();
  ~ScratchDir();
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
  const std::string& path() const { return path_; }
  std::string file(const std::string& name) const { return path_ + "/" + name; }
  std::vector<std::string> entries() const;  // names of the files in it, sorted

 private:
  std::string path_;
};

struct VideoFacts {
  std::string codec;         // e.g. "h264"
  std::string pixel_format;  // e.g. "yuv420p"
  int width = 0;
  int height = 0;
  int fps_num = 0;  // the stream's average frame rate
  int fps_den = 0;
  long long frames_in_index = 0;  // sample count recorded by the container
  std::vector<Image> frames;      // every decoded frame, as RGB (BT.709, limited range)
};

// Opens and decodes the whole file; fails the current test (and returns what it has) on error.
VideoFacts read_video(const std::string& path);

// Four-letter types of the top-level MP4 boxes in file order, e.g. ftyp, moov, mdat.
std::vector<std::string> top_level_boxes(const std::string& path);

std::vector<char> file_bytes(const std::string& path);

}  // namespace tissu::test
