// A whole figure: every panel's scene is loaded and checked first (bad input renders
// nothing), then each panel is run to its iteration, drawn at the panel size, and the
// panels are composed with their captions and the title.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "figure/figure_spec.h"
#include "figure/panel.h"

namespace tissu {

// Optional per-panel observer (e.g. an MP4 writer): it sees the run's frames.
class PanelObserver {
 public:
  virtual ~PanelObserver() = default;
  // Called before panel `index` runs; returns the iterations between frames (0 = none).
  virtual long long begin(size_t index, const PanelSpec& panel, const Scene& scene) = 0;
  virtual void frame(const Model& model, const State& state) = 0;
  // Called after the run (also when it diverged).
  virtual void end(size_t index, const PanelRun& run) = 0;
};

struct PanelOutcome {
  std::string scene_name;
  int triangles = 0;
  long long requested = 0;     // iteration asked for
  long long shown = 0;         // iteration shown
  std::optional<Divergence> divergence;
  double simulate_seconds = 0; // wall time of the simulation, s
  double render_seconds = 0;   // wall time of drawing the panel, s
  std::string caption;         // as drawn
  std::string scene_file;      // the panel's scene file
};

struct FigureResult {
  Image image;
  std::vector<PanelOutcome> panels;
};

// Loads (and validates) every panel's scene. Throws InputError.
std::vector<Scene> load_figure_scenes(const FigureSpec& figure);

// Progress callback: called after each panel with its outcome.
using PanelProgress = std::function<void(size_t index, const PanelOutcome& outcome)>;

// The image is the same bits on every run unless `caption_times` puts the measured wall
// times ({T}) into the captions; PanelOutcome always holds them.
FigureResult render_figure(const FigureSpec& figure, const std::vector<Scene>& scenes,
                           PanelObserver* observer = nullptr, const PanelProgress& progress = {},
                           bool caption_times = false);

}  // namespace tissu
