#include "app/run_loop.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "app/signals.h"
#include "mesh/obj_writer.h"
#include "physics/forces.h"
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

RunResult run_simulation(const Scene& scene, Simulation& sim, const RunOptions& options,
                         FrameSink* sink) {
  const auto run_start = std::chrono::steady_clock::now();
  const Model& model = sim.model;
  State& state = sim.state;
  Stepper stepper(model, state, options.threads);
  RunResult result;
  result.threads = force_threads(options.threads, model);
  Vec3List last_frame_x = state.x;  // final.obj falls back to it after a divergence

  bool end_recorded = false;  // the state the run ends on is the last row
  auto record = [&](const State& shown) {
    const FrameStats stats = measure_frame(model, shown);
    result.frames.push_back(stats);
    if (options.check) result.checks.push_back(check_frame(model, shown));
    last_frame_x = shown.x;
    end_recorded = &shown == &state;
    return stats;
  };
  auto emit_frame = [&](const State& shown) {
    const FrameStats stats = record(shown);
    if (sink) sink->frame(model, shown, stats);
  };

  // Frame k is at k / frame_rate; a frame within this fraction of a step of a step's end
  // is that step's state (the time summed over steps drifts by round-off).
  constexpr double kSameTime = 1e-6;
  const double rate = options.frame_rate > 0.0 ? options.frame_rate : 1.0 / model.dt;
  long long next_frame = 0;
  auto frame_time = [&](long long k) { return static_cast<double>(k) / rate; };

  // False once the run has the frames it wants: it then stops (Stopped).
  auto wants_frame = [&] {
    const bool enough = options.max_frames >= 0 && next_frame >= options.max_frames;
    return !enough && (!sink || sink->wants_more());
  };

  // The progress line counts frames and simulated time, up to the last frame.
  long long total_frames = frame_count(static_cast<double>(scene.steps) * model.dt, rate);
  if (options.max_frames >= 0) total_frames = std::min(total_frames, options.max_frames);
  ProgressBar progress = ProgressBar::on_stderr(options.progress_label, scene.steps);
  progress.count_frames(total_frames, frame_time(total_frames - 1));
  const State& before = stepper.before();  // kept when a frame falls inside the step
  State between;

  for (long long s = 0;; ++s) {
    const bool last = s == scene.steps;
    // Frames that fall inside the step just taken, then one at its end.
    if (s > 0 && stepper.has_before()) {
      while (wants_frame() && frame_time(next_frame) < state.t - kSameTime * model.dt) {
        const double w = (frame_time(next_frame) - before.t) / (state.t - before.t);
        between.t = frame_time(next_frame);
        between.step = before.step;
        between.x.resize(state.x.size());
        between.v.resize(state.v.size());
        for (size_t i = 0; i < state.x.size(); ++i) {
          between.x[i] = (1.0 - w) * before.x[i] + w * state.x[i];
          between.v[i] = (1.0 - w) * before.v[i] + w * state.v[i];
        }
        emit_frame(between);
        ++next_frame;
      }
    }
    if (wants_frame() && std::fabs(frame_time(next_frame) - state.t) <= kSameTime * model.dt) {
      emit_frame(state);
      ++next_frame;
    }
    if (!options.obj_dir.empty() && options.obj_every > 0 && s % options.obj_every == 0) {
      write_obj(obj_frame_path(options.obj_dir, s), state.x, model.rest_uv, model.triangles);
    }
    if (options.progress) progress.update_frames(next_frame, state.t);
    if (last) break;
    if (!wants_frame()) {
      result.status = RunStatus::Stopped;
      break;
    }
    if (interrupt_requested()) {
      result.status = RunStatus::Interrupted;
      break;
    }
    // Keep the state before the step when the next frame falls inside it.
    const std::optional<Divergence> divergence =
        stepper.advance(frame_time(next_frame) < state.t + (1.0 - kSameTime) * model.dt);
    end_recorded = false;
    result.steps_done = s + 1;
    if (divergence) {
      result.status = RunStatus::Diverged;
      result.divergence = divergence;
      break;
    }
  }
  result.totals = stepper.totals();
  result.times.simulate = result.totals.wall_seconds;
  // The report ends on the state the run ends on, also between frame times (not a frame
  // of the video).
  if (!end_recorded && result.status != RunStatus::Diverged) {
    result.end = measure_frame(model, state);
    last_frame_x = state.x;
  }
  if (options.progress) progress.finish();
  if (!options.obj_dir.empty()) {
    const bool good = result.status != RunStatus::Diverged;
    write_obj((std::filesystem::path(options.obj_dir) / "final.obj").string(),
              good ? state.x : last_frame_x, model.rest_uv, model.triangles);
  }
  result.times.total = seconds_since(run_start);
  return result;
}

}  // namespace tissu
