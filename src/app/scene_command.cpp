// tissu run and tissu render: load and validate everything first (bad input writes
// nothing), then simulate (and render), then always write the report.
#include <algorithm>
#include <filesystem>
#include <iostream>

#include "app/cli.h"
#include "app/commands.h"
#include "app/divergence_hint.h"
#include "app/earlier_outputs.h"
#include "app/frame_check.h"
#include "app/render_sink.h"
#include "app/report.h"
#include "app/run_loop.h"
#include "app/signals.h"
#include "core/output_target.h"
#include "physics/parallel.h"

namespace tissu {

namespace {

namespace fs = std::filesystem;

int exit_code_of(const RunResult& result) {
  switch (result.status) {
    case RunStatus::Ok:
    case RunStatus::Stopped:  // as asked (--frames)
      for (const FrameCheck& c : result.checks) {
        if (!c.clean()) return kExitCrossings;
      }
      return kExitOk;
    case RunStatus::Diverged: return kExitDiverged;
    case RunStatus::Interrupted: return kExitInterrupted;
  }
  return kExitOk;
}

void print_summary(const Scene& scene, const RunResult& result, long long max_frames) {
  if (result.divergence) {
    const Divergence& d = *result.divergence;
    std::cerr << "tissu: " << scene.name << ": diverged at step " << d.step << " (t = " << d.time
              << " s), vertex " << d.vertex << ": " << d.reason << "\n";
  } else if (result.status == RunStatus::Interrupted) {
    std::cerr << "tissu: " << scene.name << ": interrupted after " << result.steps_done
              << " steps\n";
  } else if (result.status == RunStatus::Stopped) {
    std::cerr << "tissu: " << scene.name << ": stopped at --frames " << max_frames << " after "
              << result.steps_done << " of " << scene.steps << " steps\n";
  }
  if (!result.checks.empty()) {
    const CheckSummary summary = summarize_checks(result.checks);
    const FrameCheck* first = summary.first;
    std::cerr << "tissu: " << scene.name << ": check: " << summary.frames_with_crossings << " of "
              << result.checks.size()
              << " frames have crossing triangles (" << summary.frames_with_obstacle_crossings
              << " with a mesh obstacle)";
    if (first) std::cerr << "; first at step " << first->step << " (t = " << first->time << " s): " << first->first;
    std::cerr << "\n";
  }
}

std::string parent_dir(const std::string& path) {
  const std::string parent = fs::path(path).parent_path().string();
  return parent.empty() ? "." : parent;
}

// Frame indices of `count` stills spread evenly over `frames` frames (last one included).
std::vector<long long> still_frames(long long frames, int count) {
  std::vector<long long> out;
  for (int i = 1; i <= count; ++i) out.push_back((frames - 1) * i / count);
  return out;
}

int run_scene(const std::vector<std::string>& args, bool render) {
  SceneCommandOptions options;
  if (!parse_scene_command(args, render, options)) return kExitOk;
  const Scene scene = load_scene(options.scene_file, options.overrides);
  const RenderSettings settings = render_settings_of(scene);
  Simulation sim = build_simulation(scene);
  if (scene.position_correction && !is_explicit(scene.integrator)) {
    // Discontinuous at its threshold, it tears cloth at frame-rate steps (docs/paper.md).
    std::cerr << "warning: " << options.scene_file << ": position_correction with "
              << integrator_name(scene.integrator)
              << ": the paper's correction is made for explicit steps; at dt = " << scene.dt
              << " s it moves neighbours apart by up to half its threshold\n";
  }

  RunOptions run;
  run.frame_rate = frames_per_simulated_second(settings);
  // More threads than processors would only make them wait for each other.
  run.threads = std::min(options.threads > 0 ? options.threads : kMaxThreads,
                         available_processors());
  run.progress = !options.quiet;
  run.check = options.check;
  run.progress_label = render ? "render" : "simulate";

  std::unique_ptr<RenderSink> sink;
  RenderOutputs outputs;
  if (render) {
    const long long frames = frame_count(scene.steps * scene.dt, run.frame_rate);
    // --frames N stops the run after frame N - 1 (status stopped), unless the scene ends
    // there anyway.
    if (options.max_frames > 0 && options.max_frames < frames) run.max_frames = options.max_frames;
    const long long shown = run.max_frames > 0 ? run.max_frames : frames;
    outputs.progress = !options.quiet;
    if (options.mp4) outputs.mp4_path = (fs::path(options.out_dir) / (scene.name + ".mp4")).string();
    if (options.png) outputs.png_dir = (fs::path(options.out_dir) / "png").string();
    if (options.stills > 0) {
      outputs.stills_dir = (fs::path(options.out_dir) / "stills").string();
      outputs.still_frames = still_frames(shown, options.stills);
    }
  }

  // Output locations are checked before anything is written; if one of them cannot be
  // created (or the renderer cannot start), the directories made so far are removed again.
  // Named output files that are not regular files (devices, pipes, directories, symbolic
  // links) are refused before the run, and before anything is created; so are an earlier
  // run's outputs, unless -y: then they are removed once the renderer has started.
  check_output_target(options.report_path);
  if (!outputs.mp4_path.empty()) check_output_target(outputs.mp4_path);
  if (options.obj_every > 0) {
    run.obj_every = options.obj_every;
    run.obj_dir = (fs::path(options.out_dir) / "obj").string();
  }
  const EarlierOutputs earlier({options.report_path, outputs.mp4_path, outputs.png_dir,
                                outputs.stills_dir, run.obj_dir});
  if (!options.overwrite) earlier.refuse();
  OutputDirs dirs;
  try {
    dirs.prepare(options.out_dir);
    dirs.prepare(parent_dir(options.report_path));
    if (!run.obj_dir.empty()) dirs.prepare(run.obj_dir);
    if (!outputs.png_dir.empty()) dirs.prepare(outputs.png_dir);
    if (!outputs.stills_dir.empty()) dirs.prepare(outputs.stills_dir);
    if (render) sink = std::make_unique<RenderSink>(settings, outputs);
    earlier.remove();
  } catch (...) {
    sink.reset();
    dirs.remove_created_if_empty();
    throw;
  }

  install_interrupt_handlers();
  RunResult result;
  try {
    result = run_simulation(scene, sim, run, sink.get());
    if (sink) {
      sink->finish();  // the video plays up to the last frame, also after a divergence
      sink->add_times(result.times);
      if (sink->frames_drawn() < sink->frames()) {
        // Interrupted while held frames were drawn: the outputs end at the last one drawn.
        result.status = RunStatus::Interrupted;
        result.frames.resize(std::min(result.frames.size(), static_cast<size_t>(sink->frames_drawn())));
      }
    }
  } catch (...) {
    if (sink) sink->abort();
    throw;
  }
  nlohmann::ordered_json report = make_report(scene, sim.model, result);
  print_summary(scene, result, run.max_frames);
  if (result.divergence) {
    if (!options.quiet) std::cerr << "tissu: " << scene.name << ": looking for a step that works\n";
    const DivergenceHint hint = find_divergence_hint(scene, build_simulation(scene),
                                                     *result.divergence, options.overrides);
    const std::string text = divergence_hint_text(hint);
    std::cerr << "tissu: " << scene.name << ": " << text << "\n";
    report["divergence"]["hint"] = {
        {"working_dt", hint.working_dt ? nlohmann::ordered_json(*hint.working_dt) : nullptr},
        {"checked_until", hint.checked_until},
        {"smallest_failed_dt", hint.smallest_failed_dt},
        {"stability_command", hint.stability_command},
        {"text", text}};
  }
  write_text_file(options.report_path, report.dump(1) + "\n");
  if (!options.quiet) {
    if (!outputs.mp4_path.empty()) std::cerr << "tissu: video: " << outputs.mp4_path << "\n";
    if (!outputs.stills_dir.empty()) std::cerr << "tissu: stills: " << outputs.stills_dir << "/\n";
    if (!outputs.png_dir.empty()) std::cerr << "tissu: frames: " << outputs.png_dir << "/\n";
    std::cerr << "tissu: report: " << options.report_path << "\n";
  }
  return exit_code_of(result);
}

}  // namespace

int command_run(const std::vector<std::string>& args) { return run_scene(args, false); }

int command_render(const std::vector<std::string>& args) { return run_scene(args, true); }

}  // namespace tissu
