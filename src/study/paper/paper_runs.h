// What the paper's experiments share: its three integrators and their names, its scenes
// loaded with overrides, and one run of a model to an iteration on the study's probe.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "physics/step.h"
#include "scene/scene.h"

namespace tissu {

// Explicit Euler (eq. 9), modified Euler (eq. 10) and the paper's scheme, in this order.
extern const std::vector<Integrator> kPaperIntegrators;

// The integrator as the paper's tables name it ("explicit Euler (eq. 9)", ...).
const char* paper_name(Integrator integrator);

struct PaperScene {
  std::string file;
  Scene scene;
  Simulation sim;
};

// Reads, overrides (null removes a key) and builds a scene; InputError names the file.
PaperScene load_paper_scene(const std::string& file,
                            const std::vector<std::pair<std::string, Json>>& overrides = {});

struct PaperRun {
  State state;                           // the last good state
  std::optional<Divergence> divergence;  // where the run diverged, if it did
  double seconds = 0.0;                  // wall time of the steps, s
};

// Runs `model` (its integrator, dt and settings as given) from `start` for `steps`
// iterations, stopping at a divergence; `observe` sees the first state and each later one.
PaperRun run_paper_case(const Model& model, const State& start, long long steps,
                        const std::function<void(const State&)>& observe = {});

// "none", or "threshold T m, N iterations".
std::string correction_text(const Model& model);

// The iteration of divergence, or "none".
std::string divergence_cell(const PaperRun& run);

}  // namespace tissu
