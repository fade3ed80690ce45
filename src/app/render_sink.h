// Rendering during a run. Each frame of the simulation loop is copied into a small queue;
// a render thread draws it off screen, reads it back and hands it to the encoder pipeline
// (MP4 and/or PNG files), which encodes on a worker thread of its own. So the simulation of
// the next frames, the drawing of this one and the encoding of the previous ones overlap.
#pragma once

#include <condition_variable>
#include <deque>
#include <exception>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "app/run_loop.h"
#include "view/scene_render_settings.h"
#include "render/renderer.h"
#include "video/frame_encoder_pipeline.h"

namespace tissu {

// Video frames per simulated second: fps * slow_motion.
double frames_per_simulated_second(const RenderSettings& settings);

struct RenderOutputs {
  std::string mp4_path;  // "" = no video
  std::string png_dir;   // "" = no PNG sequence
  std::string stills_dir;  // "" = no stills
  std::vector<long long> still_frames;  // frame indices written to stills_dir
  long long max_frames = -1;           // stop after this many frames; -1 = all
  bool render_thread = true;  // draw on a thread of its own (false: in frame(), on the caller's)
  bool pass_timing = false;   // profiling: time each renderer pass (slower); see pass_times()
  bool progress = false;      // a progress line on stderr while held frames are drawn
};

// CPU time of the rendering, s (wall times are in StageTimes and RenderSink::wait_times()).
struct RenderCpuTimes {
  double draw = 0.0;          // thread that drives the renderer: Renderer::draw()
  double readback = 0.0;      // same thread: Renderer::read_rgb()
  double rasterizer = 0.0;    // llvmpipe's rasterizer threads
  double thread_total = 0.0;  // the render thread, all of it (0 without a render thread)
};

// With the automatic camera framing the whole run (render.camera.framing "run", the
// default), frames are held in memory until the run ends, then drawn: the camera then
// frames everything the run shows, from the first frame on.
class RenderSink : public FrameSink {
 public:
  // Creates the renderer (on the render thread) and the outputs. Throws RenderError or
  // OutputError, as the renderer and the MP4 writer do.
  RenderSink(const RenderSettings& settings, const RenderOutputs& outputs);
  ~RenderSink() override;  // abort() unless finish() succeeded
  RenderSink(const RenderSink&) = delete;
  RenderSink& operator=(const RenderSink&) = delete;

  // Queues (or holds) the frame (copies positions, obstacles and text) and returns; blocks
  // while two frames wait to be drawn. Rethrows an error of the render thread or the encoder.
  void frame(const Model& model, const State& state, const FrameStats& stats) override;
  bool wants_more() const override;

  // Draws and encodes every frame queued or held so far (also after a divergence or an
  // interrupt) and completes the video, which plays up to the last frame. An interrupt
  // while held frames are drawn ends the video at the last frame drawn. Rethrows a render
  // or encoder error (OutputError for files).
  void finish();
  // Drops queued frames, stops the render thread, removes the unfinished video. Never throws.
  void abort() noexcept;

  // Stage times, s: drawing, read-back, running the encoder, and the time the simulation
  // loop waited for a free place in the render queue (as encode_wait).
  void add_times(StageTimes& times) const;
  long long frames() const { return frame_index_; }
  // Frames drawn into the outputs; fewer than frames() after an interrupt while drawing
  // held frames. Valid after finish().
  long long frames_drawn() const { return frames_drawn_; }
  // Valid after finish().
  RenderCpuTimes cpu_times() const { return cpu_; }
  double encoder_queue_wait_seconds() const { return encoder_wait_s_; }  // render thread, wall
  std::vector<RenderPassTime> pass_times() const { return pass_times_; }

 private:
  struct Topology;
  struct Job;
  struct Output;
  struct CameraFit;

  void render_thread_main();
  void render(Output& out, const Job& job);
  void end_output(Output& out) noexcept;
  void rethrow_error();
  void submit(Job&& job);
  void draw_held_frames();

  RenderSettings settings_;
  RenderOutputs outputs_;
  std::unique_ptr<FrameEncoderPipeline> pipeline_;
  std::unique_ptr<Output> serial_;  // renderer and scratch when there is no render thread
  std::shared_ptr<const Topology> topology_;
  long long frame_index_ = 0;   // frames queued
  double edge_length_ = 0.0;    // m, mean cloth edge length at the first frame
  long long frames_drawn_ = 0;
  // Framing the whole run: the frames held until it ends, and the bounds of what they show.
  bool hold_frames_ = false;
  std::vector<Job> held_;
  Eigen::AlignedBox3d shown_;
  bool closed_ = false;         // finish() or abort() ran

  // Shared with the render thread.
  std::thread thread_;
  mutable std::mutex mutex_;
  std::condition_variable job_ready_, space_free_, started_;
  std::deque<Job> queue_;
  bool thread_started_ = false;
  bool no_more_jobs_ = false;
  bool drop_jobs_ = false;
  std::exception_ptr error_;

  // Times, summed on the thread that draws; read after it ended.
  double render_s_ = 0.0, readback_s_ = 0.0, encoder_wait_s_ = 0.0, queue_wait_s_ = 0.0;
  RenderCpuTimes cpu_;
  std::vector<RenderPassTime> pass_times_;
};

}  // namespace tissu
