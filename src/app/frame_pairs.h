// The frames of the two inputs of `tissu compare`, paired: two PNG files, two directories
// of PNG frames (paired by file name) or two MP4 files (paired by position).
#pragma once

#include <memory>
#include <optional>
#include <string>

#include "video/image.h"

namespace tissu {

struct FramePair {
  std::string name;  // for messages: "frame_000003.png", or "frame 3" of a video
  std::string stem;  // for file names: "frame_000003"
  std::optional<Image> a;  // absent when the frame exists on the other side only
  std::optional<Image> b;
};

class FramePairs {
 public:
  virtual ~FramePairs() = default;
  // The next pair, in file-name order (directories) or video order; false after the last.
  // InputError "<file>: <problem>" when a frame cannot be read.
  virtual bool next(FramePair& pair) = 0;
};

// Opens both inputs. InputError naming the input and the problem when one is missing or
// unreadable, is not a PNG file, a directory of PNG frames or an MP4 file, or when the
// two are not of the same kind.
std::unique_ptr<FramePairs> open_frame_pairs(const std::string& a, const std::string& b);

}  // namespace tissu
