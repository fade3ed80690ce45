#include "app/run_loop.h"

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
    case RunStatus::Diverged: return "diverged";
    case RunStatus::Interrupted: return "interrupted";
  }
  return "unknown";
}

long long steps_per_frame(double dt, double frames_per_second) {
  return std::max<long long>(1, std::llround(1.0 / (frames_per_second * dt)));
}

RunResult run_simulation(const Scene& scene, Simulation& sim, const RunOptions& options,
                         FrameSink* sink) {
  const auto run_start = std::chrono::steady_clock::now();
  const Model& model = sim.model;
  State& state = sim.state;
  Workspace ws;
  ws.threads = options.threads;
  RunResult result;
  result.threads = force_threads(options.threads, model);
  ProgressBar progress = ProgressBar::on_stderr(options.progress_label, scene.steps);
  Vec3List last_frame_x = state.x;  // final.obj falls back to it after a divergence

  auto emit_frame = [&] {
    const FrameStats stats = measure_frame(model, state);
    result.frames.push_back(stats);
    if (options.check) result.checks.push_back(check_frame(model, state));
    last_frame_x = state.x;
    if (sink) sink->frame(model, state, stats);
  };

  for (long long s = 0;; ++s) {
    const bool last = s == scene.steps;
    if (s % options.frame_every == 0 || last) emit_frame();
    if (!options.obj_dir.empty() && options.obj_every > 0 && s % options.obj_every == 0) {
      write_obj(obj_frame_path(options.obj_dir, s), state.x, model.rest_uv, model.triangles);
    }
    if (options.progress) progress.update(s);
    if (last || (sink && !sink->wants_more())) break;
    if (interrupt_requested()) {
      result.status = RunStatus::Interrupted;
      break;
    }
    const auto t0 = std::chrono::steady_clock::now();
    const std::optional<Divergence> divergence = step(model, state, ws);
    result.times.simulate += seconds_since(t0);
    result.newton_iterations += ws.newton_iterations;
    result.cg_iterations += ws.cg_iterations;
    result.contact_seconds += ws.contact_seconds;
    result.contact_proximities += ws.contact.proximities;
    result.contact_impacts += ws.contact.impacts;
    result.contact_rebuilds += ws.contact.rebuilt ? 1 : 0;
    result.contact_zones += ws.contact.zones;
    result.contact_rigid_zones += ws.contact.rigid_zones;
    result.contact_unresolved += ws.contact.unresolved;
    result.steps_done = s + 1;
    if (divergence) {
      result.status = RunStatus::Diverged;
      result.divergence = divergence;
      break;
    }
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
