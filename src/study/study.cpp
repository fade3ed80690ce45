#include "study/study.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <ostream>
#include <sstream>

#include "core/error.h"
#include "study/output.h"
#include "study/plot.h"
#include "video/png_io.h"

namespace tissu {

namespace {

// Worst RMS and worst max distance over the samples, m.
void worst(const std::vector<PositionError>& errors, double& rms, double& max) {
  rms = 0.0;
  max = 0.0;
  for (const PositionError& e : errors) {
    rms = std::max(rms, e.rms);
    max = std::max(max, e.max);
  }
}

std::vector<PositionError> compare(const std::vector<Sample>& a, const std::vector<Sample>& b) {
  std::vector<PositionError> out;
  for (size_t k = 0; k < a.size() && k < b.size(); ++k) out.push_back(position_error(a[k].x, b[k].x));
  return out;
}

bool is_dissipative(const Model& model) {
  return model.air_damping || model.wind || model.material.damping > 0.0 ||
         !model.obstacles.empty();
}

std::string mm(double metres) { return sig(metres * 1e3, 3); }

// The time a study ranks and plots by, s per simulated s.
double cost(const StudyResult& study, const ProbeResult& p) {
  return study.cpu_clock ? p.cpu_per_simulated_second() : p.wall_per_simulated_second();
}

void log_run(std::ostream* log, const std::string& what, const ProbeResult& p) {
  if (!log) return;
  *log << "study: " << what << ": " << probe_status_name(p.status);
  if (p.failure) {
    *log << " at step " << p.failure->step << " (t = " << sig(p.failure->time) << " s), vertex "
         << p.failure->vertex << ": " << p.failure->reason;
  }
  *log << "; per simulated s: " << sig(p.wall_per_simulated_second()) << " s wall, "
       << sig(p.cpu_per_simulated_second()) << " s CPU\n";
  log->flush();
}

}  // namespace

std::vector<double> dt_ladder(double dt0, double cap) {
  std::vector<double> out{dt0};
  for (double dt = 2.0 * dt0; dt <= cap * (1.0 + 1e-9); dt *= 2.0) out.push_back(dt);
  return out;
}

std::vector<double> even_samples(double duration, int count) {
  std::vector<double> out;
  for (int k = 1; k <= count; ++k) out.push_back(duration * k / count);
  return out;
}

void validate_study_options(const Scene& scene, const StudyOptions& options) {
  const double duration = static_cast<double>(scene.steps) * scene.dt;
  if (!(duration > 0.0)) throw InputError("the scene has no duration to study");
  for (double t : options.samples) {
    if (!(t > 0.0) || t > duration * (1.0 + 1e-12)) {
      throw InputError("--samples: " + sig(t, 6) + " s is outside (0, " + sig(duration, 6) +
                       "] s, the scene's duration");
    }
  }
  for (double dt : options.dts) {
    if (!(dt > 0.0)) throw InputError("--dts: time steps must be > 0");
  }
  if (options.integrators.empty()) throw InputError("--integrators: none given");
}

StudyResult run_study(const Scene& scene, const Simulation& base, const StudyOptions& options) {
  StudyResult study;
  study.scene_name = scene.name;
  study.scene_file = scene.file;
  study.vertices = base.model.num_vertices();
  study.triangles = base.model.num_triangles();
  study.duration = static_cast<double>(scene.steps) * scene.dt;
  validate_study_options(scene, options);
  study.sample_times = options.samples.empty() ? even_samples(study.duration, 4) : options.samples;
  std::sort(study.sample_times.begin(), study.sample_times.end());
  study.dissipative = is_dissipative(base.model);
  study.converged_ratio = options.converged_ratio;
  study.cpu_clock = options.cpu_clock;

  std::vector<double> dts = options.dts;
  const bool automatic = dts.empty();
  if (automatic) dts = dt_ladder(scene.dt, options.dt_cap);
  std::sort(dts.begin(), dts.end());

  ProbeSpec spec;
  spec.duration = study.duration;
  spec.sample_times = study.sample_times;
  spec.interrupted = options.interrupted;

  // Reference (ref_dt / 2) and its check run (ref_dt).
  study.ref_integrator = options.ref_integrator;
  study.ref_dt = options.ref_dt > 0.0 ? options.ref_dt : dts.front() / 16.0;
  spec.integrator = options.ref_integrator;
  spec.dt = study.ref_dt / 2.0;
  ProbeResult reference = run_probe(base, spec);
  log_run(options.log, std::string("reference ") + integrator_name(spec.integrator) + " dt " +
                           sig(spec.dt) + " s", reference);
  spec.dt = study.ref_dt;
  ProbeResult check = reference.stable() ? run_probe(base, spec) : ProbeResult{};
  if (reference.stable()) {
    log_run(options.log, std::string("reference check ") + integrator_name(spec.integrator) +
                             " dt " + sig(spec.dt) + " s", check);
  }
  if (reference.status == ProbeStatus::Interrupted || check.status == ProbeStatus::Interrupted) {
    study.interrupted = true;
    return study;
  }
  if (!reference.stable() || !check.stable()) {
    const ProbeResult& bad = reference.stable() ? check : reference;
    study.reference_stable = false;
    study.reference_failure = std::string(probe_status_name(bad.status)) +
                              (bad.failure ? " at step " + std::to_string(bad.failure->step) +
                                                 ", vertex " + std::to_string(bad.failure->vertex) +
                                                 ": " + bad.failure->reason
                                           : "");
    return study;
  }
  study.ref_errors = compare(check.samples, reference.samples);
  worst(study.ref_errors, study.ref_rms_worst, study.ref_max_worst);
  study.ref_wall_per_second = reference.wall_per_simulated_second();
  study.energy_scale = reference.energy_scale;
  const double e_ref_end = reference.samples.back().energy.total();

  // The runs: every integrator at every rung; on the automatic ladder an integrator stops
  // after its first unstable step, and the ladder stops when none is left.
  std::vector<bool> active(options.integrators.size(), true);
  for (double dt : dts) {
    if (automatic && std::none_of(active.begin(), active.end(), [](bool a) { return a; })) break;
    for (size_t i = 0; i < options.integrators.size(); ++i) {
      if (!active[i]) continue;
      spec.integrator = options.integrators[i];
      spec.dt = dt;
      StudyRun run;
      run.integrator = spec.integrator;
      run.dt = dt;
      run.probe = run_probe(base, spec);
      log_run(options.log, std::string(integrator_name(run.integrator)) + " dt " + sig(dt) + " s",
              run.probe);
      if (run.probe.status == ProbeStatus::Interrupted) {
        study.interrupted = true;
        return study;
      }
      if (run.probe.stable()) {
        run.errors = compare(run.probe.samples, reference.samples);
        worst(run.errors, run.rms_worst, run.max_worst);
        const double e_end = run.probe.samples.back().energy.total();
        run.energy_drift = (e_end - run.probe.energy_start) / study.energy_scale;
        run.energy_vs_ref = (e_end - e_ref_end) / study.energy_scale;
        for (const Sample& s : run.probe.samples) run.any_interpolated |= s.interpolated;
      } else if (automatic) {
        active[i] = false;
      }
      run.probe.samples.clear();
      run.probe.samples.shrink_to_fit();
      study.runs.push_back(std::move(run));
    }
  }

  // Convergence of the reference against the smallest error reported.
  study.smallest_rms = INFINITY;
  for (const StudyRun& r : study.runs) {
    if (r.probe.stable()) study.smallest_rms = std::min(study.smallest_rms, r.rms_worst);
  }
  study.converged = std::isfinite(study.smallest_rms) &&
                    study.ref_rms_worst * options.converged_ratio <= study.smallest_rms;
  return study;
}

std::string study_csv(const StudyResult& study) {
  std::ostringstream out;
  out << "integrator,dt_s,steps,steps_done,status,stable,wall_s_per_sim_s,cpu_s_per_sim_s,"
         "rms_error_mm,max_error_mm";
  for (double t : study.sample_times) out << ",rms_mm_t" << sig(t, 6) << ",max_mm_t" << sig(t, 6);
  out << ",energy_drift_rel,energy_vs_ref_rel,energy_max_j,newton_iterations,cg_iterations,"
         "failure_step,failure_vertex,failure_reason\n";
  for (const StudyRun& r : study.runs) {
    const ProbeResult& p = r.probe;
    out << integrator_name(r.integrator) << "," << sig(r.dt, 6) << "," << p.steps << ","
        << p.steps_done << "," << probe_status_name(p.status) << "," << (p.stable() ? 1 : 0)
        << "," << sig(p.wall_per_simulated_second(), 4) << ","
        << sig(p.cpu_per_simulated_second(), 4) << ",";
    if (p.stable()) {
      out << sig(r.rms_worst * 1e3, 4) << "," << sig(r.max_worst * 1e3, 4);
      for (const PositionError& e : r.errors) out << "," << sig(e.rms * 1e3, 4) << "," << sig(e.max * 1e3, 4);
      out << "," << sig(r.energy_drift, 4) << "," << sig(r.energy_vs_ref, 4);
    } else {
      out << ",";
      for (size_t k = 0; k < study.sample_times.size(); ++k) out << ",,";
      out << ",,";
    }
    out << "," << sig(p.energy_max, 6) << "," << p.newton_iterations << "," << p.cg_iterations
        << ",";
    if (p.failure) {
      std::string reason = p.failure->reason;
      std::replace(reason.begin(), reason.end(), '"', '\'');
      out << p.failure->step << "," << p.failure->vertex << ",\"" << reason << "\"";
    } else {
      out << ",,";
    }
    out << "\n";
  }
  return out.str();
}

std::string study_markdown(const StudyResult& study, const std::string& plot_file_name) {
  std::ostringstream md;
  md << "# Accuracy study: " << study.scene_name << "\n\n";
  md << "Scene `" << study.scene_file << "`: " << study.vertices << " vertices, " << study.triangles
     << " triangles, " << sig(study.duration, 6) << " s simulated; errors measured at t =";
  for (size_t k = 0; k < study.sample_times.size(); ++k) {
    md << (k ? ", " : " ") << sig(study.sample_times[k], 6);
  }
  md << " s.\n\n";
  if (!study.reference_stable) {
    md << "**The reference run (" << integrator_name(study.ref_integrator) << ", dt "
       << sig(study.ref_dt / 2) << " s / " << sig(study.ref_dt) << " s) was not stable: "
       << study.reference_failure << ". No result.**\n";
    return md.str();
  }
  md << "Reference: " << integrator_name(study.ref_integrator) << " at dt = "
     << sig(study.ref_dt / 2) << " s. Its own error, estimated by its distance to the same "
     << "method at dt = " << sig(study.ref_dt) << " s (for a first-order method the error of the "
     << "finer run is about that distance): RMS " << mm(study.ref_rms_worst) << " mm, max "
     << mm(study.ref_max_worst) << " mm (worst sample); per sample, RMS";
  for (size_t k = 0; k < study.ref_errors.size(); ++k) {
    md << (k ? ", " : " ") << mm(study.ref_errors[k].rms) << " mm at " << sig(study.sample_times[k], 6)
       << " s";
  }
  md << ".\n\n";
  if (study.converged) {
    md << "**Converged:** the reference error (RMS " << mm(study.ref_rms_worst)
       << " mm) is " << sig(study.smallest_rms / std::max(study.ref_rms_worst, 1e-300), 3)
       << " times below the smallest RMS error reported (" << mm(study.smallest_rms)
       << " mm; required: " << sig(study.converged_ratio) << " times).\n\n";
  } else {
    md << "**Not converged:** the reference error (RMS " << mm(study.ref_rms_worst)
       << " mm) is not " << sig(study.converged_ratio)
       << " times below the smallest RMS error reported (" << mm(study.smallest_rms)
       << " mm); errors near that size are not meaningful. Rerun with a smaller --ref-dt.\n\n";
  }
  md << "Errors: distance of each vertex to its reference position; RMS over all vertices and "
        "the largest, worst over the sample times, in mm. Time: wall-clock and CPU seconds "
        "spent stepping per simulated second (one thread; wall above CPU means the machine "
        "was shared). Energy E = kinetic + elastic + gravity "
        "potential; ";
  if (study.dissipative) {
    md << "the scene dissipates or receives energy (damping, wind or contact), so the energy "
          "column is (E(T) - E_ref(T)) / W, ";
  } else {
    md << "the scene conserves energy, so the energy column is the drift (E(T) - E(0)) / W, ";
  }
  md << "with W = " << sig(study.energy_scale) << " J the work gravity and external drivers "
     << "can do (see src/study/metrics.h).\n\n";

  md << "| integrator | dt (s) | steps | status | wall s / sim s | CPU s / sim s | RMS error "
        "(mm) | max error (mm) | energy (% of W) | Newton its | CG its |\n";
  md << "|---|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const StudyRun& r : study.runs) {
    const ProbeResult& p = r.probe;
    md << "| " << integrator_name(r.integrator) << " | " << sig(r.dt) << " | " << p.steps << " | ";
    if (p.stable()) {
      md << "stable | " << sig(p.wall_per_simulated_second()) << " | "
         << sig(p.cpu_per_simulated_second()) << " | " << mm(r.rms_worst)
         << " | " << mm(r.max_worst) << " | "
         << sig(100.0 * (study.dissipative ? r.energy_vs_ref : r.energy_drift), 3) << " | ";
    } else {
      md << "**" << probe_status_name(p.status) << "**";
      if (p.failure) md << " at step " << p.failure->step << ", vertex " << p.failure->vertex;
      md << " | " << sig(p.wall_per_simulated_second()) << " | "
         << sig(p.cpu_per_simulated_second()) << " | - | - | - | ";
    }
    md << p.newton_iterations << " | " << p.cg_iterations << " |\n";
  }
  bool interpolated = false;
  for (const StudyRun& r : study.runs) interpolated |= r.any_interpolated;
  if (interpolated) {
    md << "\nSome sample times fall between two steps of a run; those states are linearly "
          "interpolated between the steps.\n";
  }

  // Cheapest stable run within each error budget.
  md << "\n## Cheapest run per error budget\n\n";
  md << "Cheapest by " << (study.cpu_clock ? "CPU" : "wall") << " time.\n\n";
  md << "| RMS error budget (mm) | cheapest run | dt (s) | " << (study.cpu_clock ? "CPU" : "wall")
     << " s / sim s | RMS error (mm) |\n";
  md << "|---:|---|---:|---:|---:|\n";
  for (double budget_mm : {0.01, 0.1, 1.0, 10.0, 100.0}) {
    const StudyRun* best = nullptr;
    for (const StudyRun& r : study.runs) {
      if (!r.probe.stable() || r.rms_worst * 1e3 > budget_mm) continue;
      if (!best || cost(study, r.probe) < cost(study, best->probe)) {
        best = &r;
      }
    }
    md << "| " << sig(budget_mm) << " | ";
    if (best) {
      md << integrator_name(best->integrator) << " | " << sig(best->dt) << " | "
         << sig(cost(study, best->probe)) << " | " << mm(best->rms_worst) << " |\n";
    } else {
      md << "none | | | |\n";
    }
  }
  md << "\n![error against time](" << plot_file_name << ")\n";
  return md.str();
}

void write_study_csv(const StudyResult& study, const std::string& path) {
  write_text_file(path, study_csv(study));
}

void write_study_markdown(const StudyResult& study, const std::string& path,
                          const std::string& plot_file_name) {
  write_text_file(path, study_markdown(study, plot_file_name));
}

void write_study_plot(const StudyResult& study, const std::string& path) {
  LogLogPlot plot;
  plot.title = "Error against cost: " + study.scene_name;
  plot.x_label = study.cpu_clock ? "CPU time per simulated second (s/s)"
                                 : "wall time per simulated second (s/s)";
  plot.y_label = "RMS vertex error vs reference (mm)";
  const std::vector<Integrator> order = all_integrators();
  for (size_t i = 0; i < order.size(); ++i) {
    Series s;
    s.name = integrator_name(order[i]);
    s.color = series_color(static_cast<int>(i));
    s.marker = series_marker(static_cast<int>(i));
    for (const StudyRun& r : study.runs) {
      if (r.integrator != order[i] || !r.probe.stable()) continue;
      s.x.push_back(cost(study, r.probe));
      s.y.push_back(r.rms_worst * 1e3);
    }
    if (!s.x.empty()) plot.series.push_back(s);
  }
  if (study.ref_rms_worst > 0.0) {
    plot.lines.push_back({"reference error", study.ref_rms_worst * 1e3, Rgb{120, 120, 120}});
  }
  const BitmapFont font(default_font_file());
  write_png(path, render_plot(plot, font));
}

}  // namespace tissu
