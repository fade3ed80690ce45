// tissu run: simulate a scene, write the report and OBJ snapshots.
#include <filesystem>
#include <iostream>

#include "app/cli.h"
#include "app/commands.h"
#include "app/report.h"
#include "app/run_loop.h"
#include "app/signals.h"

namespace tissu {

namespace {
constexpr double kDefaultFrameRate = 30.0;  // report rows per simulated second
}

int run_exit_code(const RunResult& result) {
  switch (result.status) {
    case RunStatus::Ok: return kExitOk;
    case RunStatus::Diverged: return kExitDiverged;
    case RunStatus::Interrupted: return kExitInterrupted;
  }
  return kExitOk;
}

void print_run_summary(const Scene& scene, const RunResult& result, const std::string& report) {
  if (result.divergence) {
    const Divergence& d = *result.divergence;
    std::cerr << "tissu: " << scene.name << ": diverged at step " << d.step << " (t = " << d.time
              << " s), vertex " << d.vertex << ": " << d.reason << "\n";
  } else if (result.status == RunStatus::Interrupted) {
    std::cerr << "tissu: " << scene.name << ": interrupted after " << result.steps_done
              << " steps\n";
  }
  std::cerr << "tissu: report written to " << report << "\n";
}

int command_run(const std::vector<std::string>& args) {
  SceneCommandOptions options;
  if (!parse_scene_command(args, /*render=*/false, options)) return kExitOk;
  const Scene scene = load_scene(options.scene_file, options.overrides);
  Simulation sim = build_simulation(scene);

  prepare_output_dir(options.out_dir);
  prepare_output_dir(std::filesystem::path(options.report_path).parent_path().string().empty()
                         ? "."
                         : std::filesystem::path(options.report_path).parent_path().string());
  RunOptions run;
  run.frame_every = steps_per_frame(scene.dt, kDefaultFrameRate);
  run.progress = !options.quiet;
  if (options.obj_every > 0) {
    run.obj_every = options.obj_every;
    run.obj_dir = (std::filesystem::path(options.out_dir) / "obj").string();
    prepare_output_dir(run.obj_dir);
  }

  install_interrupt_handlers();
  const RunResult result = run_simulation(scene, sim, run, nullptr);
  write_text_file(options.report_path, make_report(scene, sim.model, result).dump(1) + "\n");
  print_run_summary(scene, result, options.report_path);
  return run_exit_code(result);
}

}  // namespace tissu
