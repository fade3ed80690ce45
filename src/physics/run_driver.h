// The one run driver: steps a model to the end of a run with the Stepper and hands the
// states its observers asked for to them. Every loop around step() is made of it: tissu run
// and render (frames, OBJ snapshots, progress), studies and the paper's experiments
// (samples, monitoring) and figure panels (frames at step indices). Tested by
// tests/physics/run_driver_test.cpp.
#pragma once

#include <functional>
#include <optional>
#include <vector>

#include "physics/stepper.h"

namespace tissu {

// Where a sample was taken.
struct SamplePoint {
  double time = 0.0;        // s, the time asked for (a step's time for samples by step)
  long long steps = 0;      // steps the run had taken (the step before, when interpolated)
  bool interpolated = false;  // between two steps (positions and velocities), or a step's own
};

// How a run ended: Completed, every step taken; Stopped, an observer wanted no more;
// Diverged, a step failed; Interrupted, DriveSpec::interrupted said so.
enum class RunEnd { Completed, Stopped, Diverged, Interrupted };

struct DriveResult {
  RunEnd end = RunEnd::Completed;
  long long steps_done = 0;  // steps taken, the one that diverged included
  std::optional<Divergence> divergence;
  StepTotals totals;
};

// What a run does besides stepping; every hook is optional.
class RunObserver {
 public:
  virtual ~RunObserver() = default;
  // Time of the next sample wanted (s), not decreasing from call to call; none when the
  // observer wants no more samples by time. A sample time within DriveSpec::same_time of a
  // step's time is that step's state; one between two steps is the linear interpolation of
  // positions and velocities between them; one at or before the first state is the first state.
  virtual std::optional<double> next_sample_time() const { return std::nullopt; }
  // Samples by step: the states after a multiple of this many steps of the run (the first
  // state included); 0 = none. Delivered after the samples by time of the same state.
  virtual long long sample_every() const { return 0; }
  virtual void sample(const State& /*state*/, const SamplePoint& /*point*/) {}
  // The first state (steps 0) and the state after each step that did not diverge, before
  // that state's samples.
  virtual void reached(const State& /*state*/, long long /*steps*/) {}
  // False ends the run (RunEnd::Stopped); asked right after each step and before the next.
  virtual bool wants_more() const { return true; }
  // The state the run ends on, once, after the last step (the last good state after a
  // divergence when DriveSpec::end_on_last_good).
  virtual void finish(const State& /*state*/, const DriveResult& /*result*/) {}
};

struct DriveSpec {
  long long steps = 0;   // steps to take
  int threads = 1;       // threads for each step (same results for any count)
  // After a divergence, put the state back to the one before the failed step.
  bool end_on_last_good = false;
  // Polled before each step when set; true ends the run (RunEnd::Interrupted).
  std::function<bool()> interrupted;
  // Fraction of a step within which a sample time counts as that step's time (sample and
  // step times carry round-off).
  double same_time = 1e-6;
};

// Runs `state` of `model` for spec.steps steps, observers in the order given (each sees
// its own samples, in time order). Keeps the state before a step only when a sample falls
// inside it or end_on_last_good asks for it.
DriveResult drive(const Model& model, State& state, const DriveSpec& spec,
                  const std::vector<RunObserver*>& observers);

}  // namespace tissu
