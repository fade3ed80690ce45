// (d) The cloth hung at 3 points (figure 11) after a long run: did it come to rest?
#include <cmath>
#include <filesystem>

#include "physics/diagnostics.h"
#include "study/output.h"
#include "study/paper/experiments.h"
#include "study/paper/paper_runs.h"

namespace tissu {

namespace {

double rms_speed(const Vec3List& v) {
  double v2 = 0;
  for (const Vec3& vi : v) v2 += vi.squaredNorm();
  return std::sqrt(v2 / static_cast<double>(v.size()));
}

}  // namespace

void paper_hung(const PaperOptions& o, PaperReport& r) {
  const PaperScene l =
      load_paper_scene((std::filesystem::path(o.scenes_dir) / "hung3.json").string());
  const long long steps = o.quick ? 2000 : l.scene.steps;
  r.md += "## (d) The cloth hung at 3 points (figure 11)\n\n";
  r.md += "`scenes/paper/hung3.json` (" + std::to_string(l.sim.model.num_triangles()) +
          " triangles, " + correction_text(l.sim.model) + ") run for " + std::to_string(steps) +
          " iterations (" + printf_text("%.3f", steps * l.sim.model.dt) +
          " s). Kinetic energy and speeds at the end tell whether it came to rest.\n\n";
  MarkdownTable t({"integrator", "position correction", "status", "kinetic energy (J)",
                   "largest speed (m/s)", "RMS speed (m/s)", "largest strain"});
  for (Integrator integ : kPaperIntegrators) {
    for (bool correction : {true, false}) {
      Model m = l.sim.model;
      m.integrator = integ;
      if (!correction) m.position_correction.reset();
      const PaperRun out = run_paper_case(m, l.sim.state, steps);
      const FrameStats s = measure_frame(m, out.state);
      const auto measured = [&](double value) {
        return out.divergence ? std::string("-") : sig(value);
      };
      t.row({paper_name(integ), correction ? "yes" : "no",
             out.divergence ? "diverged at " + std::to_string(out.divergence->step)
                            : "ran " + std::to_string(out.state.step),
             measured(s.kinetic_energy), measured(s.max_speed), measured(rms_speed(out.state.v)),
             measured(s.max_strain)});
      const auto row = [&](const std::string& quantity, const std::string& value,
                           const std::string& unit) {
        r.csv.push_back({"d_hung3", l.scene.name, integrator_name(integ), m.dt, 1,
                         correction_text(m), quantity, value, unit, ""});
      };
      if (out.divergence) {
        row("divergence_iteration", std::to_string(out.divergence->step), "iteration");
      } else {
        row("kinetic_energy_end", sig(s.kinetic_energy, 6), "J");
        row("max_speed_end", sig(s.max_speed, 6), "m/s");
      }
    }
    r.say("(d) " + std::string(integrator_name(integ)) + " done");
  }
  r.md += t.text();
}

}  // namespace tissu
