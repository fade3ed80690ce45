#include "app/divergence_hint.h"

#include <algorithm>
#include <cmath>

#include "app/shell_words.h"
#include "app/signals.h"
#include "study/output.h"
#include "study/probe.h"

namespace tissu {

DivergenceHint find_divergence_hint(const Scene& scene, const Simulation& initial,
                                    const Divergence& divergence,
                                    const std::vector<std::string>& overrides,
                                    double budget) {
  DivergenceHint hint;
  const Integrator integrator = initial.model.integrator;
  hint.stability_command = "tissu stability " + shell_word(scene.file) + " --integrators " +
                           integrator_name(integrator);
  for (const std::string& o : overrides) hint.stability_command += " --set " + shell_word(o);
  const double duration = static_cast<double>(scene.steps) * scene.dt;
  hint.checked_until = std::min(duration, 2.0 * std::max(divergence.time, scene.dt));
  hint.smallest_failed_dt = scene.dt;
  const double triangles = std::max<double>(1.0, static_cast<double>(initial.model.num_triangles()));
  double spent = 0.0;
  for (double dt = scene.dt / 2; ; dt /= 2) {
    const double steps = std::ceil(hint.checked_until / dt - 1e-9);
    if ((spent + steps) * triangles > budget || interrupt_requested()) break;
    ++hint.tries;
    ProbeSpec spec;
    spec.integrator = integrator;
    spec.dt = dt;
    spec.duration = hint.checked_until;
    spec.interrupted = interrupt_requested;
    const ProbeResult p = run_probe(initial, spec);
    spent += static_cast<double>(p.steps_done);
    if (p.status == ProbeStatus::Interrupted) break;
    if (p.stable()) {
      hint.working_dt = dt;
      break;
    }
    hint.smallest_failed_dt = dt;
  }
  return hint;
}

std::string divergence_hint_text(const DivergenceHint& hint) {
  std::string text;
  if (hint.working_dt) {
    text = "a step of " + sig(*hint.working_dt) + " s runs to t = " + sig(hint.checked_until) +
           " s without diverging (" + sig(hint.smallest_failed_dt) + " s does not); ";
  } else if (hint.tries > 0) {
    text = "no step down to " + sig(hint.smallest_failed_dt) + " s got past t = " +
           sig(hint.checked_until) + " s within the hint's search; ";
  }
  return text + "the largest step for the whole run: " + hint.stability_command;
}

}  // namespace tissu
