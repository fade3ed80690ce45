#include "app/run_loop.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "app/signals.h"
#include "mesh/obj_writer.h"
#include "physics/forces.h"
#include "physics/run_driver.h"
#include "video/progress_bar.h"

namespace tissu {

namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

std::string obj_frame_path(const std::string& dir, long long step) {
  char name[32];
  std::snprintf(name, sizeof(name), "frame_%06lld.obj", step);
  return (std::filesystem::path(dir) / name).string();
}

}  // namespace


const char* run_status_name(RunStatus status) {
  switch (status) {
    case RunStatus::Ok: return "ok";
    case RunStatus::Stopped: return "stopped";
    case RunStatus::Diverged: return "diverged";
    case RunStatus::Interrupted: return "interrupted";
  }
  return "unknown";
}

long long frame_count(double duration, double frame_rate) {
  return static_cast<long long>(std::floor(duration * frame_rate + 1e-6)) + 1;
}

long long steps_per_frame(double dt, double frames_per_second) {
  return std::max<long long>(1, std::llround(1.0 / (frames_per_second * dt)));
}

namespace {

// The report's frames: one row per frame time k / rate, the crossing check, the sink, and
// the state the run ends on when it is not a frame.
class FrameRecorder : public RunObserver {
 public:
  FrameRecorder(const Model& model, const RunOptions& options, double rate, FrameSink* sink,
                RunResult& result)
      : model_(model), options_(options), rate_(rate), sink_(sink), result_(result) {}

  // False once the run has the frames it wants: it then stops (Stopped).
  bool wants_more() const override {
    const bool enough = options_.max_frames >= 0 && next_frame_ >= options_.max_frames;
    return !enough && (!sink_ || sink_->wants_more());
  }
  std::optional<double> next_sample_time() const override {
    if (!wants_more()) return std::nullopt;
    return static_cast<double>(next_frame_) / rate_;
  }
  void sample(const State& shown, const SamplePoint& point) override {
    const FrameStats stats = measure_frame(model_, shown);
    result_.frames.push_back(stats);
    if (options_.check) result_.checks.push_back(check_frame(model_, shown));
    last_frame_x_ = shown.x;
    exact_at_ = point.interpolated ? -1 : point.steps;
    if (sink_) sink_->frame(model_, shown, stats);
    ++next_frame_;
  }
  // The report ends on the state the run ends on, also between frame times (not a frame
  // of the video).
  void finish(const State& state, const DriveResult& run) override {
    const bool end_recorded = exact_at_ == run.steps_done;
    if (!end_recorded && run.end != RunEnd::Diverged) {
      result_.end = measure_frame(model_, state);
      last_frame_x_ = state.x;
    }
  }

  long long frames() const { return next_frame_; }
  const Vec3List& last_frame_x() const { return last_frame_x_; }

 private:
  const Model& model_;
  const RunOptions& options_;
  double rate_;  // frames per simulated second
  FrameSink* sink_;
  RunResult& result_;
  long long next_frame_ = 0;
  long long exact_at_ = -1;  // steps of the run at the last frame, when it was a step's state
  Vec3List last_frame_x_;
};

// OBJ snapshots every `obj_every` steps, and final.obj: the state the run ends on, or the
// last frame after a divergence.
class ObjSnapshots : public RunObserver {
 public:
  ObjSnapshots(const Model& model, const RunOptions& options, const FrameRecorder& frames)
      : model_(model), options_(options), frames_(frames) {}

  long long sample_every() const override { return options_.obj_every; }
  void sample(const State& state, const SamplePoint& point) override {
    write_obj(obj_frame_path(options_.obj_dir, point.steps), state.x, model_.rest_uv,
              model_.triangles);
  }
  void finish(const State& state, const DriveResult& run) override {
    const bool good = run.end != RunEnd::Diverged;
    write_obj((std::filesystem::path(options_.obj_dir) / "final.obj").string(),
              good ? state.x : frames_.last_frame_x(), model_.rest_uv, model_.triangles);
  }

 private:
  const Model& model_;
  const RunOptions& options_;
  const FrameRecorder& frames_;
};

// The progress line: frames and simulated time, after each step's frames.
class ProgressLine : public RunObserver {
 public:
  ProgressLine(ProgressBar& bar, const FrameRecorder& frames) : bar_(bar), frames_(frames) {}
  long long sample_every() const override { return 1; }
  void sample(const State& state, const SamplePoint&) override {
    bar_.update_frames(frames_.frames(), state.t);
  }
  void finish(const State&, const DriveResult&) override { bar_.finish(); }

 private:
  ProgressBar& bar_;
  const FrameRecorder& frames_;
};

RunStatus run_status(RunEnd end) {
  switch (end) {
    case RunEnd::Completed: return RunStatus::Ok;
    case RunEnd::Stopped: return RunStatus::Stopped;
    case RunEnd::Diverged: return RunStatus::Diverged;
    case RunEnd::Interrupted: return RunStatus::Interrupted;
  }
  return RunStatus::Ok;
}

}  // namespace

RunResult run_simulation(const Scene& scene, Simulation& sim, const RunOptions& options,
                         FrameSink* sink) {
  const auto run_start = std::chrono::steady_clock::now();
  const Model& model = sim.model;
  RunResult result;
  result.threads = force_threads(options.threads, model);

  // Frame k is at k / rate, the state of the step that ends there or interpolated.
  const double rate = options.frame_rate > 0.0 ? options.frame_rate : 1.0 / model.dt;
  FrameRecorder frames(model, options, rate, sink, result);
  std::vector<RunObserver*> observers = {&frames};
  ObjSnapshots obj(model, options, frames);
  if (!options.obj_dir.empty()) observers.push_back(&obj);

  // The progress line counts frames and simulated time, up to the last frame.
  long long total_frames = frame_count(static_cast<double>(scene.steps) * model.dt, rate);
  if (options.max_frames >= 0) total_frames = std::min(total_frames, options.max_frames);
  ProgressBar bar = ProgressBar::on_stderr(options.progress_label, scene.steps);
  bar.count_frames(total_frames, static_cast<double>(total_frames - 1) / rate);
  ProgressLine progress(bar, frames);
  if (options.progress) observers.push_back(&progress);

  DriveSpec spec;
  spec.steps = scene.steps;
  spec.threads = options.threads;
  spec.interrupted = interrupt_requested;
  const DriveResult run = drive(model, sim.state, spec, observers);
  result.status = run_status(run.end);
  result.steps_done = run.steps_done;
  result.divergence = run.divergence;
  result.totals = run.totals;
  result.times.simulate = result.totals.wall_seconds;
  result.times.total = seconds_since(run_start);
  return result;
}

}  // namespace tissu
