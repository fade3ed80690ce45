// Accuracy study: one scene, several integrators, a ladder of time steps; error against a
// converged reference, time per simulated second, energy drift and stability of each run.
// `tissu study` drives it; docs/accuracy.md publishes its results.
#pragma once

#include <functional>
#include <iosfwd>
#include <string>
#include <vector>

#include "study/probe.h"

namespace tissu {

struct StudyOptions {
  std::vector<Integrator> integrators = all_integrators();
  std::vector<double> dts;      // s; empty = scene dt * 2^k up to dt_cap, while any is stable
  double dt_cap = 1.0 / 30.0;   // s, top of the automatic ladder
  std::vector<double> samples;  // s; empty = 4 evenly spaced: T/4, T/2, 3T/4, T
  double ref_dt = 0.0;          // s; 0 = smallest dt / 16. The reference runs at ref_dt / 2,
                                // checked against a run at ref_dt.
  Integrator ref_integrator = Integrator::SymplecticEuler;
  double converged_ratio = 10.0;  // reference error must be this many times below the smallest
  bool cpu_clock = false;         // plot and rank by thread CPU time instead of wall time
  std::ostream* log = nullptr;    // one line per run when set
  std::function<bool()> interrupted;
};

struct StudyRun {
  Integrator integrator = Integrator::SymplecticEuler;
  double dt = 0.0;  // s
  ProbeResult probe;  // samples dropped once the errors are measured
  std::vector<PositionError> errors;  // per sample time (empty when unstable)
  double rms_worst = 0.0;   // m, largest RMS error over the samples
  double max_worst = 0.0;   // m, largest vertex distance over the samples
  double energy_drift = 0.0;   // (E(T) - E(0)) / W
  double energy_vs_ref = 0.0;  // (E(T) - E_ref(T)) / W
  bool any_interpolated = false;
};

struct StudyResult {
  std::string scene_name, scene_file;
  int vertices = 0, triangles = 0;
  double duration = 0.0;             // s
  std::vector<double> sample_times;  // s
  bool dissipative = false;  // damping, wind, material damping or contact: compare energy to the reference
  double energy_scale = 0.0;  // W, J (see energy_scale())

  // Reference: ref_integrator at ref_dt / 2; its error estimated by the distance to the
  // ref_dt run.
  Integrator ref_integrator = Integrator::SymplecticEuler;
  double ref_dt = 0.0;          // s (the check run); the reference itself is ref_dt / 2
  bool reference_stable = true;
  std::string reference_failure;
  std::vector<PositionError> ref_errors;  // per sample
  double ref_rms_worst = 0.0, ref_max_worst = 0.0;  // m
  double ref_wall_per_second = 0.0;                 // s/s of the reference run
  double smallest_rms = 0.0;    // m, smallest rms_worst over stable runs
  bool converged = false;       // ref_rms_worst * converged_ratio <= smallest_rms
  double converged_ratio = 10.0;
  bool interrupted = false;
  bool cpu_clock = false;  // time axis of the plot and the budget table: CPU instead of wall

  std::vector<StudyRun> runs;
};

// Checks the options against the scene (sample times within its duration, steps > 0);
// InputError otherwise. run_study calls it first.
void validate_study_options(const Scene& scene, const StudyOptions& options);

// Runs the study on a built simulation (scene values: dt, steps, name, file).
StudyResult run_study(const Scene& scene, const Simulation& base, const StudyOptions& options);

// Geometric time-step ladder dt0 * 2^k, k = 0, 1, ... while <= cap (dt0 always included).
std::vector<double> dt_ladder(double dt0, double cap);

// Default sample times: `count` evenly spaced, the last at `duration`.
std::vector<double> even_samples(double duration, int count);

// Outputs: study.csv (one row per run, per-sample errors), study.md (tables, convergence
// statement, cheapest run per error budget), study.png (error against wall time, log-log).
void write_study_csv(const StudyResult& study, const std::string& path);
void write_study_markdown(const StudyResult& study, const std::string& path,
                          const std::string& plot_file_name);
void write_study_plot(const StudyResult& study, const std::string& path);

// Text written to study.md (exposed for tests).
std::string study_markdown(const StudyResult& study, const std::string& plot_file_name);
std::string study_csv(const StudyResult& study);

}  // namespace tissu
