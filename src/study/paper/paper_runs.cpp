#include "study/paper/paper_runs.h"

#include "core/error.h"
#include "figure/panel.h"
#include "study/output.h"
#include "study/probe.h"

namespace tissu {

const std::vector<Integrator> kPaperIntegrators = {
    Integrator::ExplicitEuler, Integrator::SymplecticEuler, Integrator::BenameurDjedi};

const char* paper_name(Integrator integrator) {
  switch (integrator) {
    case Integrator::ExplicitEuler: return "explicit Euler (eq. 9)";
    case Integrator::SymplecticEuler: return "modified Euler (eq. 10)";
    case Integrator::BenameurDjedi: return "paper's scheme, h F/(2m)";
    default: return integrator_name(integrator);
  }
}

PaperScene load_paper_scene(const std::string& file,
                            const std::vector<std::pair<std::string, Json>>& overrides) {
  Json doc = read_scene_json(file);
  for (const auto& [key, value] : overrides) apply_panel_override(doc, key, value);
  PaperScene loaded;
  loaded.file = file;
  try {
    loaded.scene = parse_scene(doc, file);
  } catch (const InputError& e) {
    throw InputError(file + ": " + e.what());
  }
  loaded.sim = build_simulation(loaded.scene);
  return loaded;
}

PaperRun run_paper_case(const Model& model, const State& start, long long steps,
                        const std::function<void(const State&)>& observe) {
  ProbeSpec spec;
  spec.integrator = model.integrator;
  spec.dt = model.dt;
  spec.steps = steps;
  spec.monitored = false;
  spec.keep_end = true;
  spec.observe = observe;
  ProbeResult probe = run_probe(Simulation{model, start}, spec);
  return {std::move(probe.end), probe.failure, probe.wall_seconds};
}

std::string correction_text(const Model& model) {
  if (!model.position_correction) return "none";
  return "threshold " + sig(model.position_correction->threshold, 6) + " m, " +
         std::to_string(model.position_correction->iterations) + " iterations";
}

std::string divergence_cell(const PaperRun& run) {
  return run.divergence ? std::to_string(run.divergence->step) : std::string("none");
}

}  // namespace tissu
