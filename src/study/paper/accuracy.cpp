// (c) Distance of each integrator's result from a converged small-step reference, and what
// the paper's halving of every acceleration (h F / (2 m)) does to a free fall.
#include <cmath>
#include <filesystem>
#include <map>

#include "core/error.h"
#include "study/metrics.h"
#include "study/output.h"
#include "study/paper/experiments.h"
#include "study/paper/paper_runs.h"

namespace tissu {

namespace {

namespace fs = std::filesystem;

const double kGravity = 9.81;  // m/s^2, the scenes' |g|

// The model with `integrator`, the step dt / 2^k and, unless `correction`, no correction.
Model variant(const Model& base, Integrator integrator, int k, bool correction) {
  Model m = base;
  m.integrator = integrator;
  if (!correction) m.position_correction.reset();
  m.dt = base.dt / std::pow(2.0, k);
  return m;
}

// Modified Euler without correction at dt / 2^k, k = 3 .. finest, to T; the table of their
// differences goes into the report. Returns the finest state.
State reference(const PaperScene& l, PaperReport& r, long long iterations, int finest) {
  const double dt0 = l.sim.model.dt;
  std::map<int, State> ref;
  for (int k = 3; k <= finest; ++k) {
    const Model m = variant(l.sim.model, Integrator::SymplecticEuler, k, false);
    const PaperRun out = run_paper_case(m, l.sim.state, iterations << k);
    if (out.divergence) {
      throw OutputError("paper experiments: the reference run at dt = " + sig(m.dt, 6) +
                        " s diverged at iteration " + std::to_string(out.divergence->step));
    }
    ref[k] = out.state;
    r.say("(c) reference k = " + std::to_string(k) + " done");
  }
  MarkdownTable conv(
      {"k", "step (s)", "iterations", "RMS distance to k + 1 (mm)", "ratio to the previous"});
  double previous = 0.0;
  for (int k = 3; k < finest; ++k) {
    const double d = position_error(ref[k].x, ref[k + 1].x).rms;
    conv.row({std::to_string(k), sig(dt0 / std::pow(2.0, k), 6), std::to_string(iterations << k),
              sig(1e3 * d, 4), previous > 0 ? printf_text("%.2f", previous / d) : "-"});
    r.csv.push_back({"c_reference_convergence", l.scene.name, "symplectic_euler",
                     dt0 / std::pow(2.0, k), 1, "none", "rms_distance_to_half_step", sig(d, 6),
                     "m", ""});
    previous = d;
  }
  r.md += "Convergence of the reference (first order: each halving should halve the "
          "difference, ratio 2):\n\n" + conv.text();
  return ref[finest];
}

// Each integrator at the figures' step (with and without correction) and at smaller steps.
void distances(const PaperOptions& o, const PaperScene& l, PaperReport& r, long long iterations,
               const State& ref) {
  const Model& base = l.sim.model;
  const Vec3 start_com = centre_of_mass(base, l.sim.state.x);
  const double ref_drop = start_com.z() - centre_of_mass(base, ref.x).z();
  MarkdownTable t({"integrator", "step (s)", "position correction", "iterations",
                   "RMS distance (mm)", "largest distance (mm)", "centre-of-mass drop (mm)",
                   "drop / reference drop"});
  auto add = [&](Integrator integ, int k, bool correction) {
    const Model m = variant(base, integ, k, correction);
    const long long n = iterations << k;
    const PaperRun out = run_paper_case(m, l.sim.state, n);
    const std::string corr = correction ? "yes" : "no";
    const auto row = [&](const std::string& quantity, const std::string& value,
                         const std::string& unit) {
      r.csv.push_back({"c_accuracy", l.scene.name, integrator_name(integ), m.dt, 1,
                       correction_text(m), quantity, value, unit, ""});
    };
    if (out.divergence) {
      t.row({paper_name(integ), sig(m.dt, 6), corr,
             "diverged at " + std::to_string(out.divergence->step), "-", "-", "-", "-"});
      row("divergence_iteration", std::to_string(out.divergence->step), "iteration");
      return;
    }
    const PositionError e = position_error(out.state.x, ref.x);
    const double drop = start_com.z() - centre_of_mass(base, out.state.x).z();
    t.row({paper_name(integ), sig(m.dt, 6), corr, std::to_string(n), sig(1e3 * e.rms),
           sig(1e3 * e.max), printf_text("%.2f", 1e3 * drop),
           printf_text("%.3f", drop / ref_drop)});
    row("rms_distance_to_reference", sig(e.rms, 6), "m");
    row("max_distance_to_reference", sig(e.max, 6), "m");
    row("com_drop_over_reference", sig(drop / ref_drop, 6), "");
  };
  for (Integrator integ : kPaperIntegrators) {
    add(integ, 0, true);
    add(integ, 0, false);
    for (int k = 3; k <= (o.quick ? 3 : 5); ++k) add(integ, k, false);
    r.say("(c) " + std::string(integrator_name(integ)) + " done");
  }
  r.md += "Each integrator at the figures' step (with and without correction) and at smaller "
          "steps without correction:\n\n" + t.text();
}

// The discrete free-fall drop after n steps of h and its formula's text.
std::pair<double, const char*> free_fall_formula(Integrator integ, double h, double n) {
  switch (integ) {
    case Integrator::ExplicitEuler: return {kGravity * h * h * n * (n - 1) / 2, "g h^2 n(n-1)/2"};
    case Integrator::SymplecticEuler: return {kGravity * h * h * n * (n + 1) / 2, "g h^2 n(n+1)/2"};
    default: return {kGravity * h * h * n * (n + 1) / 4, "g h^2 n(n+1)/4"};
  }
}

// Free fall: no pins, no air, no obstacles; the exact discrete answers.
void free_fall(const std::string& file, PaperReport& r, long long iterations) {
  const PaperScene ff = load_paper_scene(file, {{"cloth.pins", Json()}, {"air_damping", Json()}});
  const double g = kGravity;
  const double dt0 = ff.sim.model.dt;
  const double T = static_cast<double>(iterations) * dt0;
  const double vcap = ff.sim.model.position_correction
                          ? ff.sim.model.position_correction->threshold / dt0
                          : 0.0;
  r.md += "### Free fall: the paper's h F / (2 m) halves gravity\n\n";
  r.md += "The same piece without its pins and without air friction falls freely to T = " +
          sig(T, 6) + " s, with the scene's position correction (speed cap threshold / dt = " +
          (vcap > 0 ? sig(vcap, 6) + " m/s at every step: the threshold is scaled with dt"
                    : std::string("none")) +
          ", above the speed reached, g T = " + sig(g * T) +
          " m/s). A rigid translation has no elastic force, so an integrator that stays stable "
          "follows its exact discrete formula (h the step, n the iterations); an unstable one "
          "amplifies the round-off in the elastic forces until it shows. Continuous free fall: "
          "g T^2 / 2 = " + printf_text("%.4f", 1e3 * 0.5 * g * T * T) + " mm.\n\n";
  MarkdownTable f({"integrator", "step (s)", "iterations", "formula for the drop",
                   "formula (mm)", "measured drop (mm)", "relative difference",
                   "drop / (g T^2 / 2)"});
  for (Integrator integ : kPaperIntegrators) {
    for (int k : {0, 3}) {
      Model m = variant(ff.sim.model, integ, k, true);
      // Same speed cap threshold / dt at every step.
      if (m.position_correction) m.position_correction->threshold /= std::pow(2.0, k);
      const long long steps = iterations << k;
      const PaperRun out = run_paper_case(m, ff.sim.state, steps);
      const double h = m.dt;
      const auto [formula, text] = free_fall_formula(integ, h, static_cast<double>(steps));
      if (out.divergence) {
        f.row({paper_name(integ), sig(h, 6), "diverged at " + std::to_string(out.divergence->step),
               text, printf_text("%.4f", 1e3 * formula), "-", "-", "-"});
        continue;
      }
      const double drop =
          centre_of_mass(m, ff.sim.state.x).z() - centre_of_mass(m, out.state.x).z();
      f.row({paper_name(integ), sig(h, 6), std::to_string(steps), text,
             printf_text("%.4f", 1e3 * formula), printf_text("%.4f", 1e3 * drop),
             printf_text("%.1e", (drop - formula) / formula),
             printf_text("%.4f", drop / (0.5 * g * T * T))});
      r.csv.push_back({"c_free_fall", ff.scene.name, integrator_name(integ), h, 1,
                       correction_text(m), "com_drop", sig(drop, 6), "m", ""});
      r.csv.push_back({"c_free_fall", ff.scene.name, integrator_name(integ), h, 1,
                       correction_text(m), "com_drop_formula", sig(formula, 6), "m", ""});
    }
  }
  r.md += f.text();
}

}  // namespace

void paper_accuracy(const PaperOptions& o, PaperReport& r, long long iterations) {
  const std::string file = (fs::path(o.scenes_dir) / "piece990.json").string();
  const PaperScene l = load_paper_scene(file);
  const double dt0 = l.sim.model.dt;
  const double T = static_cast<double>(iterations) * dt0;
  const int finest = o.quick ? 4 : 6;  // reference step dt / 2^finest
  r.md += "## (c) Distance from a converged reference\n\n";
  r.md += "The reference is the 990-triangle piece run with modified (symplectic) Euler "
          "without position correction at dt / 2^k, to the same time T = " +
          std::to_string(iterations) + " x " + sig(dt0, 6) + " s = " + sig(T, 6) +
          " s. Distances are root-mean-square (and largest) over the vertices of the position "
          "differences at T.\n\n";
  const State ref = reference(l, r, iterations, finest);
  const double ref_drop = centre_of_mass(l.sim.model, l.sim.state.x).z() -
                          centre_of_mass(l.sim.model, ref.x).z();
  r.md += "Reference: k = " + std::to_string(finest) + " (dt = " +
          sig(dt0 / std::pow(2.0, finest), 6) +
          " s); its own error is about the last difference above. Its centre of mass has "
          "dropped by " + printf_text("%.2f", 1e3 * ref_drop) + " mm at T.\n\n";
  distances(o, l, r, iterations, ref);
  free_fall(file, r, iterations);
}

}  // namespace tissu
