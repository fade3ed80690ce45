// One measured run of a scene with a chosen integrator and time step: the state at
// requested sample times, the time spent stepping, and whether the run stayed stable.
// The accuracy study and the stability search are both made of probes.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "physics/step.h"
#include "scene/scene.h"
#include "study/metrics.h"

namespace tissu {

// How a probe ended. Everything but Ok and Interrupted means "unstable".
enum class ProbeStatus {
  Ok,
  Diverged,         // step() reported a non-finite value or a runaway speed
  EnergyUnbounded,  // total energy rose above start + margin * energy_scale
  Penetration,      // a vertex ended a step inside an obstacle
  Interrupted,      // the caller asked to stop
};
const char* probe_status_name(ProbeStatus status);

struct ProbeSpec {
  Integrator integrator = Integrator::SymplecticEuler;
  double dt = 1e-3;        // s
  double duration = 1.0;   // s; the run takes ceil(duration / dt) steps
  std::vector<double> sample_times;  // s, ascending, within [0, duration]
  // Total energy and obstacle clearance are checked every `monitor_every` steps (0 = about
  // 256 checks per run) and after the last step; divergence is checked every step.
  long long monitor_every = 0;
  double energy_margin = 1.0;            // see energy_scale()
  double penetration_tolerance = 1e-6;   // m below an obstacle surface that counts as inside
  std::function<bool()> interrupted;     // polled every step when set
  // Exactly this many steps when >= 0 (duration is then ignored).
  long long steps = -1;
  // false: only a divergence ends the run (no energy or clearance checks).
  bool monitored = true;
  // Keep the state the run ends on in ProbeResult::end (the last good one after a divergence).
  bool keep_end = false;
  // Sees the first state and the state after every step that did not diverge.
  std::function<void(const State&)> observe;
};

// The state at one sample time. Sample times that fall between two steps are linearly
// interpolated between them (positions and velocities), exact otherwise.
struct Sample {
  double time = 0.0;  // s
  bool interpolated = false;
  Vec3List x;         // m
  Energy energy;      // J, of the (interpolated) state
};

struct ProbeResult {
  ProbeStatus status = ProbeStatus::Ok;
  std::optional<Divergence> failure;  // step, time, vertex and reason when unstable
  long long steps = 0;        // steps requested
  long long steps_done = 0;
  double simulated_time = 0.0;  // s, steps_done * dt
  double wall_seconds = 0.0;    // s spent in step() (monitoring excluded)
  double cpu_seconds = 0.0;     // s of this thread's CPU time in step()
  std::vector<Sample> samples;  // only the sample times reached
  double energy_start = 0.0;    // J
  double energy_max = 0.0;      // J, largest total energy checked
  double energy_bound = 0.0;    // J, start + margin * scale
  double energy_scale = 0.0;    // J
  std::optional<double> min_clearance;  // m, smallest checked (with obstacles)
  long long newton_iterations = 0;
  long long cg_iterations = 0;
  State end;  // with ProbeSpec::keep_end; empty otherwise

  bool stable() const { return status == ProbeStatus::Ok; }
  double wall_per_simulated_second() const;  // s/s
  double cpu_per_simulated_second() const;   // s/s
};

// Runs a copy of `base` (Model and initial State built from a scene) with the spec's
// integrator and time step. `base` is not modified.
ProbeResult run_probe(const Simulation& base, const ProbeSpec& spec);

// Integrator by scene name ("explicit_euler", ...); InputError listing the names otherwise.
Integrator parse_integrator_name(const std::string& name);
// Every integrator the physics module has, in the order of the Integrator enum.
std::vector<Integrator> all_integrators();

}  // namespace tissu
