// Writes RGB frames as an H.264 MP4 that browsers play (yuv420p, 'moov' atom first).
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "video/image.h"

namespace tissu {

// Frames per second as a fraction: FrameRate(30), FrameRate(30000, 1001), FrameRate(29.97).
struct FrameRate {
  int num = 30;
  int den = 1;
  FrameRate(int num, int den = 1) : num(num), den(den) {}
  FrameRate(double fps);  // nearest fraction with numbers up to 100000; NaN or <= 0 stays invalid
  double value() const { return double(num) / double(den); }
};

struct Mp4Options {
  int crf = 20;                      // x264 constant rate factor: 0 lossless .. 51 worst
  std::string preset = "veryfast";   // x264 speed preset
  std::string tune;                  // x264 tune ("animation", "film", ...); "" = none
  // More x264 settings, "key=value:key=value"; "" = none. Sub-pixel motion refinement 1
  // instead of veryfast's 2, and no B-frames instead of up to 3: on the demo about half
  // of plain veryfast's encoder time, for files a quarter larger at a slightly higher PSNR
  // (docs/video.md, "Encoder settings").
  std::string x264_params = "subme=1:bframes=0";
  int encoder_threads = 1;           // fixed, so the same frames give the same bytes everywhere
  double keyframe_interval_s = 2.0;  // a seek point at least this often
};

// Encodes frames to `path` through a hidden temporary file "dir/.name.partial":
// - finish() flushes the encoder, completes the MP4 and renames it to `path`; it also works
//   after only some frames (e.g. the simulation diverged or the user pressed Ctrl-C), but
//   with no frames at all it throws OutputError and leaves no file (browsers reject an
//   MP4 without frames);
// - abort(), or destruction without finish(), removes the temporary file;
// - any failure (bad directory, disk full, encoder error) throws OutputError naming `path`
//   and the libav or system reason, and leaves neither the final nor the temporary file.
// Odd widths or heights are padded to even ones (required by yuv420p) by repeating the last
// column or row. Not thread-safe; one writer per thread.
class Mp4Writer {
 public:
  // Creates the temporary file and writes the header. Throws InputError for a size or frame
  // rate that is not positive, OutputError when the file cannot be created.
  Mp4Writer(std::string path, int width, int height, FrameRate fps, const Mp4Options& options = {});
  ~Mp4Writer();
  Mp4Writer(Mp4Writer&&) noexcept;
  Mp4Writer& operator=(Mp4Writer&&) noexcept;

  // `rgb` holds width * height * 3 bytes, rows top to bottom (see flip_vertically for
  // bottom-up OpenGL read-backs). After a failure the writer is closed and the file removed.
  void write_frame(const std::uint8_t* rgb);
  void write_frame(const Image& frame);  // must be width x height

  void finish();
  void abort() noexcept;

  const std::string& path() const;
  int width() const;  // of the frames passed in
  int height() const;
  int video_width() const;  // in the file, even
  int video_height() const;
  long long frames_written() const;
  bool is_open() const;  // false after finish() or abort() or a failure

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace tissu
