// One panel of a figure: its scene (with the panel's overrides), the run to the iteration
// shown (keeping the last good state when the run diverges, with the wall time of the
// simulation alone), and its picture.
#pragma once

#include <functional>
#include <optional>
#include <string>

#include "figure/figure_spec.h"
#include "physics/step.h"
#include "render/renderer.h"
#include "scene/scene.h"
#include "video/image.h"

namespace tissu {

// Reads the panel's scene, applies its overrides (null removes a key) and validates it.
// Errors name the figure file, the panel and, when an override caused it, the override.
Scene load_panel_scene(const PanelSpec& panel, const std::string& figure_file);

// Applies one override to a scene document: `value` null removes the key (absent keys are
// fine), anything else is set like `--set key=value`. Throws InputError.
void apply_panel_override(Json& doc, const std::string& key, const Json& value);

// Called with the state at iteration 0, every `frame_every` iterations and at the end.
using FrameCallback = std::function<void(const Model&, const State&)>;

struct PanelRun {
  Simulation sim;         // the model, and the state shown (iteration `sim.state.step`)
  Vec3List initial_x;     // positions at iteration 0, m (camera framing)
  long long requested = 0;                 // iteration asked for
  std::optional<Divergence> divergence;    // set when the run diverged before `requested`
  double simulate_seconds = 0.0;           // wall time spent in step(), s
  bool diverged() const { return divergence.has_value(); }
};

// Runs `scene` (its `steps` is ignored) to iteration `step`. When a step diverges, the
// state shown is the one before it (the last good state) and `divergence` says where.
PanelRun run_panel(const Scene& scene, long long step, long long frame_every = 0,
                   const FrameCallback& on_frame = {});

// Fixes the camera of a panel: the scene's, completed by automatic framing of `initial_x`
// (the first frame) so that panels of one scene at different iterations share a view.
// The panel's settings are still_render_settings() (view/scene_render_settings.h), its
// frames drawn_frame() with the mean edge length of `initial_x` (view/drawn_frame.h).
void fit_panel_camera(Renderer& renderer, const Model& model, const Vec3List& initial_x);

// Draws the state shown in `run` at `width` x `height`.
Image render_panel(const Scene& scene, const PanelRun& run, int width, int height);

// Caption values of a finished run; the measured wall time only when `wall_time` is set
// (it changes from run to run, so by default images leave it out).
CaptionValues caption_values(const Scene& scene, const PanelRun& run, bool wall_time);

// The caption of a finished run: the template expanded, plus a line
// "diverged at iteration N" when the run diverged.
std::string panel_caption(const std::string& caption_template, const Scene& scene,
                          const PanelRun& run, bool wall_time);

}  // namespace tissu
