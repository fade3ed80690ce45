#include "app/render_sink.h"

#include <pthread.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include "app/signals.h"
#include "render/cpu_clock.h"
#include "render/scene_bounds.h"
#include "video/progress_bar.h"
#include "view/drawn_frame.h"

namespace tissu {

namespace {

// Frames that may wait for the render thread; more would only hold memory, since a
// waiting frame is drawn no sooner.
constexpr std::size_t kRenderQueueCapacity = 2;

// Nice value of the render thread and of the threads it starts (llvmpipe's rasterizer
// threads, the encoder): the simulation thread, which produces every frame, comes first
// when they compete for a core; they use what it leaves (the other core, or its waits).
constexpr int kRenderThreadNice = 10;


std::string numbered_png(const std::string& dir, long long index) {
  char name[32];
  std::snprintf(name, sizeof(name), "frame_%06lld.png", index);
  return (std::filesystem::path(dir) / name).string();
}

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Thread names show in top and perf; threads inherit the name of the thread creating them.
void set_thread_name(const char* name) { pthread_setname_np(pthread_self(), name); }

std::unique_ptr<FrameEncoderPipeline> make_pipeline(const RenderSettings& settings,
                                                    const RenderOutputs& outputs) {
  std::unique_ptr<Mp4Writer> video;
  if (!outputs.mp4_path.empty()) {
    video = std::make_unique<Mp4Writer>(outputs.mp4_path, settings.width, settings.height,
                                        FrameRate(settings.fps));
  }
  return std::make_unique<FrameEncoderPipeline>(std::move(video));
}

}  // namespace

// What stays the same from frame to frame, shared by the queued frames.
struct RenderSink::Topology {
  TriList triangles;
  Vec2List rest_uv;
};

// The automatic camera of a whole run, fixed before its first frame is drawn.
struct RenderSink::CameraFit {
  Eigen::AlignedBox3d shown;
  std::vector<ObstacleShape> obstacles;
};

// One queued frame: everything the renderer needs, copied out of the simulation state.
struct RenderSink::Job {
  std::shared_ptr<const CameraFit> camera_fit;  // set on the first frame of a held run
  std::shared_ptr<const Topology> topology;
  Vec3List positions;
  std::vector<ObstacleShape> obstacles;
  std::vector<std::string> overlay_lines;
  std::vector<std::string> png_paths;  // the PNG sequence's file and/or a still
};

// The renderer and its scratch frame, owned by the thread that draws.
struct RenderSink::Output {
  std::unique_ptr<Renderer> renderer;
  FrameContent content;
  const Topology* topology = nullptr;  // the one in `content`
  double rasterizer_cpu0 = 0.0;
};

double frames_per_simulated_second(const RenderSettings& settings) {
  return settings.fps * settings.slow_motion;
}

RenderSink::RenderSink(const RenderSettings& settings, const RenderOutputs& outputs)
    : settings_(settings),
      outputs_(outputs),
      hold_frames_(!settings.camera.fixed() && settings.camera.framing == Framing::Run) {
  if (!outputs_.render_thread) {
    serial_ = std::make_unique<Output>();
    serial_->renderer = std::make_unique<Renderer>(settings_);
    serial_->renderer->set_pass_timing(outputs_.pass_timing);
    serial_->rasterizer_cpu0 = named_threads_cpu_seconds("llvmpipe");
    pipeline_ = make_pipeline(settings_, outputs_);
    return;
  }
  // The GL context must be created and used on the render thread: wait until it has made
  // the renderer and the outputs, or failed to.
  thread_ = std::thread([this] { render_thread_main(); });
  std::exception_ptr error;
  {
    std::unique_lock<std::mutex> lock(mutex_);
    started_.wait(lock, [&] { return thread_started_; });
    error = error_;
  }
  if (error) {
    thread_.join();
    if (pipeline_) pipeline_->abort();
    std::rethrow_exception(error);
  }
}

RenderSink::~RenderSink() {
  if (!closed_) abort();
}

void RenderSink::render_thread_main() {
  const double cpu0 = thread_cpu_seconds();
  // Interrupts go to the simulation thread, which finishes the run; the encoder thread,
  // created below, inherits this mask and name.
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGINT);
  sigaddset(&signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);
  // Per thread on Linux, and inherited by the threads created below. Failing is harmless.
  const int current = getpriority(PRIO_PROCESS, static_cast<id_t>(syscall(SYS_gettid)));
  setpriority(PRIO_PROCESS, static_cast<id_t>(syscall(SYS_gettid)),
              std::max(current, kRenderThreadNice));
  Output out;
  try {
    set_thread_name("tissu-render");
    out.renderer = std::make_unique<Renderer>(settings_);
    out.renderer->set_pass_timing(outputs_.pass_timing);
    out.rasterizer_cpu0 = named_threads_cpu_seconds("llvmpipe");
    set_thread_name("tissu-encode");
    pipeline_ = make_pipeline(settings_, outputs_);
    set_thread_name("tissu-render");
  } catch (...) {
    out.renderer.reset();
    std::lock_guard<std::mutex> lock(mutex_);
    error_ = std::current_exception();
    thread_started_ = true;
    started_.notify_all();
    return;
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    thread_started_ = true;
  }
  started_.notify_all();

  for (;;) {
    Job job;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      job_ready_.wait(lock, [&] { return !queue_.empty() || no_more_jobs_ || drop_jobs_; });
      if (drop_jobs_ || queue_.empty()) break;
      job = std::move(queue_.front());
      queue_.pop_front();
    }
    space_free_.notify_all();
    try {
      render(out, job);
    } catch (...) {
      std::lock_guard<std::mutex> lock(mutex_);
      error_ = std::current_exception();
      queue_.clear();
      space_free_.notify_all();
      break;
    }
  }
  end_output(out);
  cpu_.thread_total = thread_cpu_seconds() - cpu0;
}

void RenderSink::render(Output& out, const Job& job) {
  FrameContent& content = out.content;
  if (out.topology != job.topology.get()) {
    content.triangles = job.topology->triangles;
    content.rest_uv = job.topology->rest_uv;
    out.topology = job.topology.get();
  }
  content.positions = job.positions;
  content.obstacles = job.obstacles;
  content.overlay_lines = job.overlay_lines;
  if (job.camera_fit) out.renderer->fit_camera(job.camera_fit->shown, job.camera_fit->obstacles);

  auto t0 = std::chrono::steady_clock::now();
  double c0 = thread_cpu_seconds();
  out.renderer->draw(content);
  render_s_ += seconds_since(t0);
  cpu_.draw += thread_cpu_seconds() - c0;

  t0 = std::chrono::steady_clock::now();
  c0 = thread_cpu_seconds();
  Image image = pipeline_->take_frame_buffer(out.renderer->width(), out.renderer->height());
  out.renderer->read_rgb(image.rgb);
  readback_s_ += seconds_since(t0);
  cpu_.readback += thread_cpu_seconds() - c0;

  // One push per frame: the video frame, plus its PNGs (sequence and still) if any.
  if (!outputs_.mp4_path.empty() || !job.png_paths.empty()) {
    t0 = std::chrono::steady_clock::now();
    pipeline_->push(std::move(image), job.png_paths);
    encoder_wait_s_ += seconds_since(t0);
  }
}

void RenderSink::end_output(Output& out) noexcept {
  if (!out.renderer) return;
  pass_times_ = out.renderer->pass_times();
  cpu_.rasterizer = std::max(0.0, named_threads_cpu_seconds("llvmpipe") - out.rasterizer_cpu0);
  out.renderer.reset();  // the GL context goes on the thread that used it
}

bool RenderSink::wants_more() const {
  return outputs_.max_frames < 0 || frame_index_ < outputs_.max_frames;
}

void RenderSink::rethrow_error() {
  std::exception_ptr error;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    error = error_;
  }
  if (error) std::rethrow_exception(error);
}

void RenderSink::frame(const Model& model, const State& state, const FrameStats& stats) {
  if (!wants_more()) return;
  if (closed_) throw std::logic_error("RenderSink::frame: the sink is closed");
  rethrow_error();
  if (!topology_) {  // constant parts, once
    auto topology = std::make_shared<Topology>();
    topology->triangles = model.triangles;
    topology->rest_uv = model.rest_uv;
    topology_ = std::move(topology);
    edge_length_ = mean_edge_length(model, state.x);
  }
  Job job;
  job.topology = topology_;
  job.positions = state.x;
  job.obstacles = drawn_obstacles(model, state.t, edge_length_);
  if (settings_.info) {
    job.overlay_lines =
        info_overlay_lines(integrator_name(model.integrator), model.triangles.size(), stats.time);
  }
  if (!outputs_.png_dir.empty()) job.png_paths.push_back(numbered_png(outputs_.png_dir, frame_index_));
  if (std::find(outputs_.still_frames.begin(), outputs_.still_frames.end(), frame_index_) !=
      outputs_.still_frames.end()) {
    job.png_paths.push_back(numbered_png(outputs_.stills_dir, frame_index_));
  }

  ++frame_index_;
  if (hold_frames_) {
    shown_.extend(shown_bounds(job.positions, job.obstacles));
    held_.push_back(std::move(job));
    return;
  }
  submit(std::move(job));
}

void RenderSink::submit(Job&& job) {
  if (serial_) {
    render(*serial_, job);
  } else {
    const auto t0 = std::chrono::steady_clock::now();
    {
      std::unique_lock<std::mutex> lock(mutex_);
      space_free_.wait(lock, [&] { return error_ || queue_.size() < kRenderQueueCapacity; });
      if (!error_) queue_.push_back(std::move(job));
    }
    queue_wait_s_ += seconds_since(t0);
    rethrow_error();
    job_ready_.notify_one();
  }
  ++frames_drawn_;
}

void RenderSink::draw_held_frames() {
  if (held_.empty()) return;
  auto fit = std::make_shared<CameraFit>();
  fit->shown = shown_;
  fit->obstacles = held_.front().obstacles;
  held_.front().camera_fit = std::move(fit);
  std::optional<ProgressBar> progress;
  if (outputs_.progress) progress.emplace(ProgressBar::on_stderr("draw", held_.size()));
  // An interrupt that stopped the simulation leaves its frames to draw; one that comes
  // while they are drawn ends the video there.
  const bool run_interrupted = interrupt_requested();
  for (Job& job : held_) {
    if (!run_interrupted && interrupt_requested()) break;
    submit(std::move(job));
    job = Job{};  // its memory goes back as the frames are drawn
    if (progress) progress->update(frames_drawn_);
  }
  if (progress) progress->finish();
  held_.clear();
}

void RenderSink::finish() {
  if (closed_) throw std::logic_error("RenderSink::finish: the sink is closed");
  draw_held_frames();  // on error, the caller's abort() (or the destructor) cleans up
  closed_ = true;
  if (thread_.joinable()) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      no_more_jobs_ = true;
    }
    job_ready_.notify_all();
    thread_.join();  // draws what is queued
  }
  if (serial_) end_output(*serial_);
  if (error_) {
    if (pipeline_) pipeline_->abort();
    std::rethrow_exception(error_);
  }
  pipeline_->finish();
}

void RenderSink::abort() noexcept {
  closed_ = true;
  if (thread_.joinable()) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      drop_jobs_ = true;
      queue_.clear();
    }
    job_ready_.notify_all();
    thread_.join();
  }
  if (serial_) end_output(*serial_);
  if (pipeline_) pipeline_->abort();
}

void RenderSink::add_times(StageTimes& times) const {
  times.render += render_s_;
  times.readback += readback_s_;
  times.encode += pipeline_->encode_seconds() + pipeline_->png_seconds();
  times.encode_wait += serial_ ? encoder_wait_s_ : queue_wait_s_;
}

}  // namespace tissu
