#include "video/frame_encoder_pipeline.h"

#include <chrono>

#include <algorithm>
#include <stdexcept>

#include "video/png_io.h"

namespace tissu {

FrameEncoderPipeline::FrameEncoderPipeline(std::unique_ptr<Mp4Writer> video, std::size_t queue_capacity)
    : video_(std::move(video)), capacity_(std::max<std::size_t>(1, queue_capacity)) {
  worker_ = std::thread([this] { work(); });
}

FrameEncoderPipeline::~FrameEncoderPipeline() { abort(); }

Image FrameEncoderPipeline::take_frame_buffer(int width, int height) {
  Image image;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!spare_pixels_.empty()) {
      image.rgb = std::move(spare_pixels_.back());
      spare_pixels_.pop_back();
    }
  }
  image.width = width;
  image.height = height;
  image.rgb.resize(image.byte_size());
  return image;
}

void FrameEncoderPipeline::push(Image frame, std::vector<std::string> png_paths) {
  if (video_ && (frame.width != video_->width() || frame.height != video_->height())) {
    throw std::invalid_argument(video_->path() + ": frame is " + std::to_string(frame.width) + "x" +
                                std::to_string(frame.height) + ", the video is " +
                                std::to_string(video_->width()) + "x" + std::to_string(video_->height()));
  }
  if (frame.rgb.size() != frame.byte_size()) {
    throw std::invalid_argument("frame pixel buffer does not match its width and height");
  }
  std::unique_lock<std::mutex> lock(mutex_);
  if (closed_) throw std::logic_error("FrameEncoderPipeline::push: the pipeline is closed");
  space_free_.wait(lock, [&] { return error_ || queue_.size() < capacity_; });
  if (error_) std::rethrow_exception(error_);
  queue_.push_back(Job{std::move(frame), std::move(png_paths)});
  job_ready_.notify_one();
}

void FrameEncoderPipeline::work() {
  for (;;) {
    Job job;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      job_ready_.wait(lock, [&] { return !queue_.empty() || no_more_jobs_; });
      if (queue_.empty()) return;
      job = std::move(queue_.front());
      queue_.pop_front();
    }
    const auto start = std::chrono::steady_clock::now();
    double png_seconds = 0.0;
    try {
      if (video_) video_->write_frame(job.frame);
      const auto png_start = std::chrono::steady_clock::now();
      for (const std::string& path : job.png_paths) write_png(path, job.frame);
      png_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - png_start).count();
    } catch (...) {
      std::lock_guard<std::mutex> lock(mutex_);
      error_ = std::current_exception();
      queue_.clear();
      space_free_.notify_all();
      return;
    }
    const double busy = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::lock_guard<std::mutex> lock(mutex_);
    encode_seconds_ += busy - png_seconds;
    png_seconds_ += png_seconds;
    ++frames_done_;
    if (spare_pixels_.size() <= capacity_) spare_pixels_.push_back(std::move(job.frame.rgb));
    space_free_.notify_all();
  }
}

void FrameEncoderPipeline::stop_worker(bool drop_queue) noexcept {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (drop_queue) queue_.clear();
    no_more_jobs_ = true;
    closed_ = true;
  }
  job_ready_.notify_all();
  if (worker_.joinable()) worker_.join();
}

void FrameEncoderPipeline::rethrow_worker_error() {
  std::exception_ptr error;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    error = error_;
  }
  if (error) {
    if (video_) video_->abort();
    std::rethrow_exception(error);
  }
}

void FrameEncoderPipeline::finish() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (closed_ && !error_) throw std::logic_error("FrameEncoderPipeline::finish: the pipeline is closed");
  }
  stop_worker(false);
  rethrow_worker_error();
  if (video_) video_->finish();
}

void FrameEncoderPipeline::abort() noexcept {
  stop_worker(true);
  if (video_) video_->abort();
}

long long FrameEncoderPipeline::frames_done() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return frames_done_;
}

double FrameEncoderPipeline::encode_seconds() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return encode_seconds_;
}

double FrameEncoderPipeline::png_seconds() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return png_seconds_;
}

}  // namespace tissu
