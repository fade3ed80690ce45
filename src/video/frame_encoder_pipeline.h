// Encodes frames on a worker thread while the caller renders the next ones.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <deque>
#include <exception>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "video/image.h"
#include "video/mp4_writer.h"

namespace tissu {

// The producer (render loop) pushes RGB frames; a worker thread converts and encodes them in
// order and writes PNGs of the frames the producer asks for. At most `queue_capacity` frames
// wait; push() blocks while the queue is full, so a slow encoder slows rendering instead of
// filling memory. The first error on the worker (e.g. disk full) is rethrown by the next
// push() and by finish(), and the temporary video file is removed. The output is the same as
// writing the frames with Mp4Writer directly, so it is bit-identical from run to run.
class FrameEncoderPipeline {
 public:
  // `video` may be null to write PNGs only.
  explicit FrameEncoderPipeline(std::unique_ptr<Mp4Writer> video, std::size_t queue_capacity = 2);
  ~FrameEncoderPipeline();  // abort() unless finish() succeeded
  FrameEncoderPipeline(const FrameEncoderPipeline&) = delete;
  FrameEncoderPipeline& operator=(const FrameEncoderPipeline&) = delete;

  // A width x height image to render into, reusing the pixel memory of encoded frames.
  // Its pixel values are unspecified.
  Image take_frame_buffer(int width, int height);

  // Queues `frame` (rows top to bottom) for the video and for a PNG file at each of
  // `png_paths` (a frame of a PNG sequence can also be a still). Blocks while the queue is
  // full.
  void push(Image frame, std::vector<std::string> png_paths = {});

  // Encodes what is queued, completes the MP4 and moves it into place.
  void finish();

  // Drops queued frames, stops the worker and removes the temporary video file. Never throws.
  void abort() noexcept;

  long long frames_done() const;  // frames the worker has completed
  double encode_seconds() const;  // worker time spent converting and encoding video, s
  double png_seconds() const;     // worker time spent writing PNG files, s

 private:
  struct Job {
    Image frame;
    std::vector<std::string> png_paths;
  };

  void work();
  void stop_worker(bool drop_queue) noexcept;
  void rethrow_worker_error();

  std::unique_ptr<Mp4Writer> video_;
  const std::size_t capacity_;
  mutable std::mutex mutex_;
  std::condition_variable job_ready_;   // worker waits: a job, or the end
  std::condition_variable space_free_;  // producer waits: room in the queue, or an error
  std::deque<Job> queue_;
  std::vector<std::vector<std::uint8_t>> spare_pixels_;  // buffers of encoded frames
  std::exception_ptr error_;
  bool no_more_jobs_ = false;
  bool closed_ = false;  // finish() or abort() ran
  long long frames_done_ = 0;
  double encode_seconds_ = 0.0;
  double png_seconds_ = 0.0;
  std::thread worker_;
};

}  // namespace tissu
