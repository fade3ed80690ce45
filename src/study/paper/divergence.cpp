// (b) Divergence without position correction on the 990-triangle piece, and how the point of
// divergence moves with the time step, the stiffness and the correction's settings.
#include <algorithm>
#include <cmath>
#include <filesystem>

#include "physics/diagnostics.h"
#include "study/metrics.h"
#include "study/output.h"
#include "study/paper/experiments.h"
#include "study/paper/paper_runs.h"

namespace tissu {

namespace {

namespace fs = std::filesystem;

long long paper_divergence(Integrator i) { return i == Integrator::BenameurDjedi ? 115 : 32; }

void scale_stiffness(Material& m, double s) {
  m.weft *= s;
  m.warp *= s;
  m.coupling *= s;
  m.shear *= s;
}

// Each integrator with and without the scene's correction, next to the paper's iteration.
void with_and_without(const PaperScene& l, PaperReport& r, long long iterations) {
  const Model& base = l.sim.model;
  MarkdownTable t({"integrator", "paper: diverges after", "ours without correction: diverges at",
                   "why", "with correction: iterations run", "max speed at the end (m/s)",
                   "largest strain at the end"});
  for (Integrator integ : kPaperIntegrators) {
    Model without = base;
    without.integrator = integ;
    without.position_correction.reset();
    const PaperRun a = run_paper_case(without, l.sim.state, iterations);
    Model with = base;
    with.integrator = integ;
    const PaperRun b = run_paper_case(with, l.sim.state, iterations);
    const FrameStats stats = measure_frame(with, b.state);
    t.row({paper_name(integ), std::to_string(paper_divergence(integ)), divergence_cell(a),
           a.divergence ? a.divergence->reason : "-",
           b.divergence ? "diverged at " + std::to_string(b.divergence->step)
                        : std::to_string(b.state.step),
           sig(stats.max_speed), sig(stats.max_strain)});
    r.csv.push_back({"b_divergence", l.scene.name, integrator_name(integ), base.dt, 1, "none",
                     "divergence_iteration", divergence_cell(a), "iteration",
                     std::to_string(paper_divergence(integ))});
    r.csv.push_back({"b_divergence", l.scene.name, integrator_name(integ), base.dt, 1,
                     correction_text(with), "iterations_run", std::to_string(b.state.step),
                     "iteration", "2000"});
    r.csv.push_back({"b_divergence", l.scene.name, integrator_name(integ), base.dt, 1,
                     correction_text(with), "max_speed_end", sig(stats.max_speed, 6), "m/s", ""});
    r.say("(b) " + std::string(integrator_name(integ)) + ": without correction " +
          divergence_cell(a));
  }
  r.md += t.text();
}

// Iteration of divergence over time steps x stiffness scales, per integrator.
void step_and_stiffness(const PaperOptions& o, const PaperScene& l, PaperReport& r,
                        long long iterations) {
  const Model& base = l.sim.model;
  const std::vector<double> dts = o.quick ? std::vector<double>{1e-4, 1.3e-4}
                                          : std::vector<double>{5e-5, 7.5e-5, 1e-4, 1.15e-4,
                                                                1.3e-4, 1.5e-4, 2e-4};
  const std::vector<double> scales =
      o.quick ? std::vector<double>{0.5, 1} : std::vector<double>{0.25, 0.5, 1, 2, 4};
  r.md += "### Where the divergence point moves with the time step and the stiffness\n\n";
  r.md += "Iteration of divergence without position correction (\"none\": ran " +
          std::to_string(iterations) +
          " iterations). The stiffness scale multiplies the four membrane stiffnesses of the "
          "material (weft, warp, coupling, shear); 1 is the " + base.material.name +
          " preset. Explicit integrators are stable below a step proportional to "
          "1/sqrt(stiffness), so the boundary should depend on dt x sqrt(scale) only; the "
          "last lines of each table give the measured boundary in that variable.\n\n";
  for (Integrator integ : kPaperIntegrators) {
    std::vector<std::string> header = {"dt (s) \\ stiffness scale"};
    for (double s : scales) header.push_back(sig(s, 6));
    MarkdownTable t(header);
    double largest_stable = 0, smallest_diverging = 1e300;
    for (double dt : dts) {
      std::vector<std::string> row = {sig(dt, 6)};
      for (double s : scales) {
        Model m = base;
        m.integrator = integ;
        m.dt = dt;
        m.position_correction.reset();
        scale_stiffness(m.material, s);
        const PaperRun out = run_paper_case(m, l.sim.state, iterations);
        row.push_back(divergence_cell(out));
        const double x = dt * std::sqrt(s);
        if (out.divergence) smallest_diverging = std::min(smallest_diverging, x);
        else largest_stable = std::max(largest_stable, x);
        r.csv.push_back({"b_divergence_table", l.scene.name, integrator_name(integ), dt, s,
                         "none", "divergence_iteration", divergence_cell(out), "iteration", ""});
      }
      t.row(row);
    }
    r.md += "**" + std::string(paper_name(integ)) + "**\n\n" + t.text();
    r.md += "Largest dt x sqrt(scale) that ran " + std::to_string(iterations) + " iterations: " +
            (largest_stable > 0 ? sig(largest_stable, 6) + " s" : std::string("none")) +
            "; smallest that diverged: " +
            (smallest_diverging < 1e300 ? sig(smallest_diverging, 6) + " s" : std::string("none")) +
            ".\n\n";
    r.csv.push_back({"b_divergence_boundary", l.scene.name, integrator_name(integ), 0, 0, "none",
                     "largest_stable_dt_sqrt_scale", sig(largest_stable, 6), "s", ""});
    r.csv.push_back({"b_divergence_boundary", l.scene.name, integrator_name(integ), 0, 0, "none",
                     "smallest_diverging_dt_sqrt_scale",
                     smallest_diverging < 1e300 ? sig(smallest_diverging, 6) : "", "s", ""});
    r.say("(b) table done: " + std::string(integrator_name(integ)));
  }
}

// Iterations run over speed caps x correction iterations, per integrator.
void correction_settings(const PaperOptions& o, const PaperScene& l, PaperReport& r,
                         long long iterations) {
  const Model& base = l.sim.model;
  const double dt0 = base.dt;
  const std::vector<double> caps =
      o.quick ? std::vector<double>{4} : std::vector<double>{1, 2, 4, 8, 16};
  const std::vector<int> its = o.quick ? std::vector<int>{1, 4} : std::vector<int>{1, 2, 4, 8};
  r.md += "### Position correction settings\n\n";
  r.md += "The correction halves a vertex's step displacement (up to n_it times) while it is "
          "longer than the threshold, so a vertex moving faster than threshold / dt is slowed: "
          "the threshold is best given as a speed cap v_cap = threshold / dt above the speeds "
          "of the real motion. Each cell: iterations run (of " + std::to_string(iterations) +
          ") and, after a slash, the largest vertex speed at the end (m/s), at dt = " +
          sig(dt0, 6) + " s.\n\n";
  for (Integrator integ : kPaperIntegrators) {
    std::vector<std::string> header = {"v_cap (m/s) \\ n_it"};
    for (int n : its) header.push_back(std::to_string(n));
    MarkdownTable t(header);
    for (double cap : caps) {
      std::vector<std::string> row = {sig(cap, 6) + " (threshold " + sig(cap * dt0, 6) + " m)"};
      for (int n : its) {
        Model m = base;
        m.integrator = integ;
        m.position_correction = PositionCorrection{cap * dt0, n};
        const PaperRun out = run_paper_case(m, l.sim.state, iterations);
        row.push_back(out.divergence ? "diverged at " + std::to_string(out.divergence->step)
                                     : std::to_string(out.state.step) + " / " +
                                           sig(max_speed(out.state.v)));
        r.csv.push_back({"b_correction_table", l.scene.name, integrator_name(integ), dt0, 1,
                         correction_text(m), "iterations_run",
                         std::to_string(out.divergence ? out.divergence->step : out.state.step),
                         "iteration", ""});
      }
      t.row(row);
    }
    r.md += "**" + std::string(paper_name(integ)) + "**\n\n" + t.text();
  }
}

}  // namespace

void paper_divergence(const PaperOptions& o, PaperReport& r, long long iterations) {
  const PaperScene l = load_paper_scene((fs::path(o.scenes_dir) / "piece990.json").string());
  const Model& base = l.sim.model;
  r.md += "## (b) Divergence without position correction\n\n";
  r.md += "The 990-triangle piece (`scenes/paper/piece990.json`: " +
          std::to_string(base.num_triangles()) + " triangles, " + base.material.name +
          ", dt = " + sig(base.dt, 6) + " s) runs up to " + std::to_string(iterations) +
          " iterations. A run diverges at the first iteration that leaves a non-finite value or "
          "a vertex faster than " + sig(base.max_speed, 6) +
          " m/s. \"With correction\" uses the scene's position correction (" +
          correction_text(base) + ").\n\n";
  with_and_without(l, r, iterations);
  step_and_stiffness(o, l, r, iterations);
  correction_settings(o, l, r, iterations);
}

}  // namespace tissu
