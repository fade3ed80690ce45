// Rendering during a run: each frame of the simulation loop is drawn off screen, read back
// and handed to the encoder pipeline (MP4 and/or PNG files), which encodes on a worker
// thread while the next frames are simulated and drawn.
#pragma once

#include <memory>
#include <string>

#include "app/run_loop.h"
#include "render/renderer.h"
#include "video/frame_encoder_pipeline.h"

namespace tissu {

// The scene's render block, validated (defaults when the scene has none).
RenderSettings render_settings_of(const Scene& scene);

// Video frames per simulated second: fps * slow_motion.
double frames_per_simulated_second(const RenderSettings& settings);

struct RenderOutputs {
  std::string mp4_path;  // "" = no video
  std::string png_dir;   // "" = no PNG sequence
  std::string stills_dir;  // "" = no stills
  std::vector<long long> still_frames;  // frame indices written to stills_dir
  long long max_frames = -1;           // stop after this many frames; -1 = all
};

class RenderSink : public FrameSink {
 public:
  RenderSink(const RenderSettings& settings, const RenderOutputs& outputs);

  void frame(const Model& model, const State& state, const FrameStats& stats) override;
  bool wants_more() const override;

  // Completes the video (it plays up to the last frame drawn). Throws OutputError.
  void finish();
  void abort() noexcept;

  // Stage times, s: drawing, read-back, waiting for and running the encoder.
  void add_times(StageTimes& times) const;
  long long frames() const { return frame_index_; }

 private:
  RenderSettings settings_;
  RenderOutputs outputs_;
  Renderer renderer_;
  std::unique_ptr<FrameEncoderPipeline> pipeline_;
  FrameContent content_;
  long long frame_index_ = 0;
  double edge_length_ = 0.0;  // m, mean cloth edge length at the first frame
  double render_s_ = 0.0, readback_s_ = 0.0, push_wait_s_ = 0.0;
};

}  // namespace tissu
