// Largest stable time step of each integrator on a scene, by bisection (bisect.h) over full
// runs of the scene's duration. A run is stable when it finishes with no divergence (finite
// values, no vertex above the scene's max_speed), total energy below start + margin * W
// (metrics.h) at every check, and no vertex inside an obstacle.
#pragma once

#include <functional>
#include <iosfwd>
#include <string>
#include <vector>

#include "study/bisect.h"
#include "study/probe.h"

namespace tissu {

struct StabilityOptions {
  std::vector<Integrator> integrators = all_integrators();
  double dt_min = 1e-7;        // s
  double dt_max = 1.0 / 30.0;  // s
  double dt_start = 0.0;       // s, first step tried; 0 = dt_max (runs above the limit end
                               // early, so searching down from the top is the cheap way)
  double precision = 0.1;      // relative bracket width
  double energy_margin = 1.0;
  std::ostream* log = nullptr;
  std::function<bool()> interrupted;
};

struct StabilityRow {
  std::string scene_name, scene_file;
  int vertices = 0, triangles = 0;
  double duration = 0.0;  // s
  Integrator integrator = Integrator::SymplecticEuler;
  BisectionResult bisection;
  ProbeResult failure;   // the run at the smallest unstable dt (samples empty)
  double seconds = 0.0;  // wall time of the whole search, s
  bool interrupted = false;
};

// Bisects every integrator on one scene.
std::vector<StabilityRow> run_stability(const Scene& scene, const Simulation& base,
                                        const StabilityOptions& options);

// "2.4e-4", ">= 0.0333" (stable at dt_max) or "< 1e-7" (unstable at dt_min).
std::string stability_limit_text(const StabilityRow& row);

std::string stability_csv(const std::vector<StabilityRow>& rows);
std::string stability_markdown(const std::vector<StabilityRow>& rows,
                               const StabilityOptions& options);

}  // namespace tissu
