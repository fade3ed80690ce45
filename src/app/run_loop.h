// The run of `tissu run` and `tissu render`, on the run driver (physics/run_driver.h): frames
// at the video frame rate, OBJ snapshots, the progress line; stops on divergence or interrupt.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "app/frame_check.h"
#include "physics/diagnostics.h"
#include "physics/step.h"
#include "physics/stepper.h"
#include "scene/scene.h"

namespace tissu {

// How a run ended: Ok, every step done; Stopped, at RunOptions::max_frames (or when the
// sink wanted no more frames) before that; Diverged; Interrupted by SIGINT or SIGTERM.
enum class RunStatus { Ok, Stopped, Diverged, Interrupted };
const char* run_status_name(RunStatus status);

// Receives the state at every frame time k / frame_rate (k = 0, 1, ...) up to the end of
// the run: the state of the step that ends there, or else the linear interpolation of
// positions and velocities between the two steps around it (the steps themselves never
// depend on the frame rate).
class FrameSink {
 public:
  virtual ~FrameSink() = default;
  virtual void frame(const Model& model, const State& state, const FrameStats& stats) = 0;
  // False once the sink has all the frames it wants: the run then stops early (Stopped).
  virtual bool wants_more() const { return true; }
};

// Wall time spent per stage, s.
struct StageTimes {
  double simulate = 0.0;
  double render = 0.0;
  double readback = 0.0;
  double encode = 0.0;       // encoder worker time (overlaps the other stages)
  double encode_wait = 0.0;  // time the loop waited for the encoder queue
  double total = 0.0;
};

struct RunOptions {
  double frame_rate = 0.0;    // frames per simulated second (fps x slow motion); 0: every step
  long long max_frames = -1;  // stop after this many frames (status Stopped); -1 = all
  int obj_every = 0;          // steps between OBJ snapshots; 0 = only final.obj (when obj_dir set)
  std::string obj_dir;        // "" = no OBJ output
  int threads = 1;            // threads for each step (same results for any count)
  bool progress = true;       // progress line on stderr
  bool check = false;         // exact crossing check of every frame (frame_check.h)
  std::string progress_label = "simulate";
};

struct RunResult {
  RunStatus status = RunStatus::Ok;
  long long steps_done = 0;
  std::optional<Divergence> divergence;
  std::vector<FrameStats> frames;  // one per video frame
  // The state the run ends on when it falls between frame times (after an interrupt, at
  // --frames, or a duration that is not a whole number of frames); not a video frame.
  std::optional<FrameStats> end;
  StageTimes times;
  int threads = 1;            // threads the steps used (force_threads of the request)
  StepTotals totals;          // what the steps did and cost, summed over the run
  std::vector<FrameCheck> checks;  // with RunOptions::check, one per frame
};

RunResult run_simulation(const Scene& scene, Simulation& sim, const RunOptions& options,
                         FrameSink* sink);

// Frames of a run of `duration` simulated seconds at `frame_rate` frames per simulated second
// (frame times 0, 1/frame_rate, ... up to the duration, within a millionth of a frame).
long long frame_count(double duration, double frame_rate);

// Steps between frames for a frame rate (frames per simulated second); at least 1. For the
// loops that show whole steps only (figure panels).
long long steps_per_frame(double dt, double frames_per_second);

}  // namespace tissu
