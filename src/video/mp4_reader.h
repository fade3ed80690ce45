// Reads the frames of a video file (tissu's MP4s, or any file libavformat opens) as RGB
// images, one at a time.
#pragma once

#include <memory>
#include <string>

#include "video/image.h"

namespace tissu {

// Decodes the file's first video stream in display order. Each frame is converted to 8-bit
// RGB as its stream is tagged (tissu's MP4s: BT.709, limited range), the way a browser
// shows it. libav's own log messages are silenced (when nobody changed libav's log level):
// every problem is an InputError "<path>: <problem>: <libav reason>".
class Mp4Reader {
 public:
  // Opens the file and its decoder; InputError when it is missing, not a video, or has no
  // video stream that can be decoded.
  explicit Mp4Reader(std::string path);
  ~Mp4Reader();
  Mp4Reader(Mp4Reader&&) noexcept;
  Mp4Reader& operator=(Mp4Reader&&) noexcept;

  // The next frame into `frame`; false after the last one. InputError when the file cannot
  // be read or decoded.
  bool read_frame(Image& frame);

  const std::string& path() const;
  long long frames_read() const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace tissu
