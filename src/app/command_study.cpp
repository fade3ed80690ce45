// tissu study and tissu stability: error against cost over a ladder of time steps, and the
// largest stable time step of each integrator (src/study, docs/accuracy.md).
#include <filesystem>
#include <iostream>
#include <sstream>

#include "app/cli.h"
#include "app/commands.h"
#include "app/signals.h"
#include "core/error.h"
#include "study/output.h"
#include "study/stability.h"
#include "study/study.h"

namespace tissu {

namespace {

namespace fs = std::filesystem;

const char* kStudyHelp =
    "usage: tissu study SCENE.json [--out DIR] [--set KEY=VALUE]... [--integrators a,b,...]\n"
    "                   [--dts d1,d2,...] [--samples t1,t2,...] [--ref-dt S] [--dt-cap S]\n"
    "                   [--cpu-time] [--quiet]\n"
    "Runs the scene with each integrator over a ladder of time steps and compares every run\n"
    "with a converged reference. Writes DIR/study.csv, DIR/study.md and DIR/study.png (error\n"
    "against wall, or CPU, time per simulated second, log-log).\n"
    "  --out DIR            output directory (default out/study/<scene file stem>)\n"
    "  --set KEY=VALUE      override a scene value, as for tissu run\n"
    "  --integrators LIST   comma-separated (default: explicit_euler, symplectic_euler,\n"
    "                       benameur_djedi, backward_euler, bdf2, implicit_midpoint)\n"
    "  --dts LIST           time steps, s (default: the scene dt times 2^k up to --dt-cap,\n"
    "                       each integrator until its first unstable step)\n"
    "  --samples LIST       times at which errors are measured, s (default T/4, T/2, 3T/4, T)\n"
    "  --ref-dt S           reference check step, s; the reference runs symplectic_euler at\n"
    "                       S/2 (default: smallest dt / 16)\n"
    "  --dt-cap S           top of the automatic ladder, s (default 1/30)\n"
    "  --cpu-time           plot and rank by thread CPU time instead of wall time (for a\n"
    "                       shared machine; both are always in the tables)\n"
    "  --quiet              no per-run lines on stderr\n"
    "Exit codes: 0 ok, 1 output error, 2 bad input, 3 reference run unstable, 130 interrupted.\n";

const char* kStabilityHelp =
    "usage: tissu stability SCENE.json... [--out DIR] [--set KEY=VALUE]...\n"
    "                       [--integrators a,b,...] [--dt-min S] [--dt-max S] [--dt-start S]\n"
    "                       [--precision P] [--energy-margin M] [--quiet]\n"
    "Bisects, for each integrator and scene, the largest time step with which the scene runs\n"
    "its whole duration stably: no divergence, total energy below start + M W (W: the work\n"
    "gravity and external drivers can do), no vertex inside an obstacle. Writes\n"
    "DIR/stability.csv and DIR/stability.md.\n"
    "  --out DIR            output directory (default out/stability/<first scene stem>)\n"
    "  --set KEY=VALUE      override a value in every scene, as for tissu run\n"
    "  --integrators LIST   comma-separated (default: all six)\n"
    "  --dt-min S, --dt-max S  search range, s (default 1e-7 and 1/30)\n"
    "  --dt-start S         first step tried, s (default --dt-max: halve while unstable,\n"
    "                       then bisect)\n"
    "  --precision P        relative width of the final bracket (default 0.1)\n"
    "  --energy-margin M    energy bound margin (default 1)\n"
    "  --quiet              no per-run lines on stderr\n"
    "Exit codes: 0 ok, 1 output error, 2 bad input, 130 interrupted.\n";

std::vector<std::string> split_list(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream ss(text);
  for (std::string item; std::getline(ss, item, ',');) {
    if (!item.empty()) out.push_back(item);
  }
  return out;
}

double parse_positive(const std::string& option, const std::string& text) {
  try {
    size_t used = 0;
    const double v = std::stod(text, &used);
    if (used == text.size() && v > 0.0 && std::isfinite(v)) return v;
  } catch (const std::exception&) {
  }
  throw InputError(option + ": expected a number > 0, got \"" + text + "\"");
}

std::vector<double> parse_positive_list(const std::string& option, const std::string& text) {
  std::vector<double> out;
  for (const std::string& item : split_list(text)) out.push_back(parse_positive(option, item));
  if (out.empty()) throw InputError(option + ": expected a comma-separated list of numbers");
  return out;
}

std::vector<Integrator> parse_integrator_list(const std::string& text) {
  std::vector<Integrator> out;
  try {
    for (const std::string& item : split_list(text)) out.push_back(parse_integrator_name(item));
  } catch (const InputError& e) {
    throw InputError(std::string("--integrators: ") + e.what());
  }
  if (out.empty()) throw InputError("--integrators: expected a comma-separated list");
  return out;
}

// Options shared by both commands; returns false when --help was printed.
struct Parsed {
  std::vector<std::string> scenes;
  std::string out_dir;
  std::vector<std::string> overrides;
  bool quiet = false;
};

// The options of study and stability: --out, --set, --quiet, SCENE.json (one, or several
// when many_scenes) and the command's own, which `extra(option, value)` takes.
bool parse(const std::vector<std::string>& args, const std::string& command, const char* help,
           bool many_scenes, Parsed& p,
           const std::function<bool(const std::string&, const OptionValue&)>& extra) {
  const bool go = walk_arguments(args, command, help, [&](const std::string& a,
                                                           const OptionValue& value) {
    if (a == "--out") {
      p.out_dir = value();
    } else if (a == "--set") {
      p.overrides.push_back(value());
    } else if (a == "--quiet") {
      p.quiet = true;
    } else if (extra(a, value)) {
    } else if (!a.empty() && a[0] == '-') {
      return false;
    } else if (p.scenes.empty() || many_scenes) {
      p.scenes.push_back(a);
    } else {
      return false;
    }
    return true;
  });
  if (!go) return false;
  if (p.scenes.empty()) throw UsageError(command + ": missing SCENE.json (see --help)");
  return true;
}

}  // namespace

int command_study(const std::vector<std::string>& args) {
  Parsed p;
  StudyOptions options;
  const bool go = parse(args, "tissu study", kStudyHelp, false, p,
                        [&](const std::string& a, const OptionValue& value) {
                          if (a == "--integrators") {
                            options.integrators = parse_integrator_list(value());
                          } else if (a == "--dts") {
                            options.dts = parse_positive_list("--dts", value());
                          } else if (a == "--samples") {
                            options.samples = parse_positive_list("--samples", value());
                          } else if (a == "--ref-dt") {
                            options.ref_dt = parse_positive("--ref-dt", value());
                          } else if (a == "--dt-cap") {
                            options.dt_cap = parse_positive("--dt-cap", value());
                          } else if (a == "--cpu-time") {
                            options.cpu_clock = true;
                          } else {
                            return false;
                          }
                          return true;
                        });
  if (!go) return kExitOk;
  const std::string out_dir = p.out_dir.empty()
                                  ? (fs::path("out") / "study" / fs::path(p.scenes[0]).stem()).string()
                                  : p.out_dir;
  const Scene scene = load_scene(p.scenes[0], p.overrides);
  validate_study_options(scene, options);
  const Simulation base = build_simulation(scene);
  prepare_output_dir(out_dir);

  install_interrupt_handlers();
  options.interrupted = interrupt_requested;
  if (!p.quiet) options.log = &std::cerr;
  const StudyResult study = run_study(scene, base, options);
  if (study.interrupted) {
    std::cerr << "tissu: study of " << scene.name << " interrupted; nothing written\n";
    return kExitInterrupted;
  }
  const fs::path dir(out_dir);
  write_study_csv(study, (dir / "study.csv").string());
  write_study_markdown(study, (dir / "study.md").string(), "study.png");
  if (!study.reference_stable) {
    std::cerr << "tissu: study of " << scene.name << ": the reference run was not stable ("
              << study.reference_failure << "); pass a smaller --ref-dt\n";
    return kExitDiverged;
  }
  write_study_plot(study, (dir / "study.png").string());
  std::cerr << "tissu: study of " << scene.name << ": " << study.runs.size() << " runs; "
            << (study.converged ? "reference converged" : "reference NOT converged") << " (error "
            << sig(study.ref_rms_worst * 1e3) << " mm RMS, smallest reported "
            << sig(study.smallest_rms * 1e3) << " mm); written to " << out_dir << "\n";
  return kExitOk;
}

int command_stability(const std::vector<std::string>& args) {
  Parsed p;
  StabilityOptions options;
  const bool go = parse(args, "tissu stability", kStabilityHelp, true, p,
                        [&](const std::string& a, const OptionValue& value) {
                          if (a == "--integrators") {
                            options.integrators = parse_integrator_list(value());
                          } else if (a == "--dt-min") {
                            options.dt_min = parse_positive("--dt-min", value());
                          } else if (a == "--dt-max") {
                            options.dt_max = parse_positive("--dt-max", value());
                          } else if (a == "--dt-start") {
                            options.dt_start = parse_positive("--dt-start", value());
                          } else if (a == "--precision") {
                            options.precision = parse_positive("--precision", value());
                          } else if (a == "--energy-margin") {
                            options.energy_margin = parse_positive("--energy-margin", value());
                          } else {
                            return false;
                          }
                          return true;
                        });
  if (!go) return kExitOk;
  if (options.dt_min > options.dt_max) throw InputError("--dt-min must not exceed --dt-max");
  const std::string out_dir =
      p.out_dir.empty() ? (fs::path("out") / "stability" / fs::path(p.scenes[0]).stem()).string()
                        : p.out_dir;
  // Load every scene first: bad input writes nothing.
  std::vector<Scene> scenes;
  for (const std::string& file : p.scenes) scenes.push_back(load_scene(file, p.overrides));
  prepare_output_dir(out_dir);

  install_interrupt_handlers();
  options.interrupted = interrupt_requested;
  if (!p.quiet) options.log = &std::cerr;
  std::vector<StabilityRow> rows;
  bool interrupted = false;
  for (const Scene& scene : scenes) {
    const Simulation base = build_simulation(scene);
    for (StabilityRow& row : run_stability(scene, base, options)) {
      interrupted |= row.interrupted;
      rows.push_back(std::move(row));
    }
    if (interrupted) break;
  }
  const fs::path dir(out_dir);
  write_text_file((dir / "stability.csv").string(), stability_csv(rows));
  write_text_file((dir / "stability.md").string(), stability_markdown(rows, options));
  std::cerr << "tissu: stability: " << rows.size() << " searches written to " << out_dir << "\n";
  return interrupted ? kExitInterrupted : kExitOk;
}

}  // namespace tissu
