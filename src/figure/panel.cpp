#include "figure/panel.h"

#include <algorithm>
#include <sstream>

#include "physics/run_driver.h"
#include "render/scene_bounds.h"
#include "view/drawn_frame.h"
#include "view/scene_render_settings.h"

namespace tissu {

namespace {

// Splits "a.b.0.c" at the dots.
std::vector<std::string> key_parts(const std::string& key) {
  std::vector<std::string> parts;
  std::stringstream ss(key);
  for (std::string part; std::getline(ss, part, '.');) parts.push_back(part);
  return parts;
}

void remove_key(Json& doc, const std::string& key) {
  const std::vector<std::string> parts = key_parts(key);
  Json* node = &doc;
  for (size_t i = 0; i + 1 < parts.size(); ++i) {
    if (node->is_object() && node->contains(parts[i])) {
      node = &(*node)[parts[i]];
    } else if (node->is_array() && !parts[i].empty() &&
               parts[i].find_first_not_of("0123456789") == std::string::npos &&
               parts[i].size() < 10 && std::stoul(parts[i]) < node->size()) {
      node = &(*node)[std::stoul(parts[i])];
    } else {
      return;  // nothing to remove
    }
  }
  if (node->is_object()) node->erase(parts.back());
}

}  // namespace

void apply_panel_override(Json& doc, const std::string& key, const Json& value) {
  if (value.is_null()) {
    remove_key(doc, key);
  } else {
    apply_override(doc, key + "=" + value.dump());
  }
}

Scene load_panel_scene(const PanelSpec& panel, const std::string& figure_file) {
  const std::string where = (figure_file.empty() ? "" : figure_file + ": ") + panel.path;
  Json doc;
  try {
    doc = read_scene_json(panel.scene);
  } catch (const InputError& e) {
    throw InputError(where + ".scene: " + e.what());
  }
  for (const auto& [key, value] : panel.overrides) {
    try {
      apply_panel_override(doc, key, value);
    } catch (const InputError& e) {
      throw InputError(where + ".overrides." + key + ": " + e.what());
    }
  }
  try {
    return parse_scene(doc, panel.scene);
  } catch (const InputError& e) {
    std::string message = e.what();
    // Name the override when the bad value came from one.
    const std::string bad = message.substr(0, message.find(':'));
    for (const auto& [key, value] : panel.overrides) {
      if (bad == key || bad.rfind(key + ".", 0) == 0 || bad.rfind(key + "[", 0) == 0) {
        throw InputError(where + ".overrides." + key + ": " + panel.scene + ": " + message);
      }
    }
    throw InputError(where + ": " + panel.scene + ": " + message);
  }
}

namespace {

// The panel's frames: iteration 0, every `frame_every` iterations, and the state the run
// ends on (the iteration shown, or the last good state after a divergence).
class PanelFrames : public RunObserver {
 public:
  PanelFrames(const Model& model, long long frame_every, const FrameCallback& on_frame)
      : model_(model), frame_every_(frame_every), on_frame_(on_frame) {}

  long long sample_every() const override { return frame_every_; }
  void sample(const State& state, const SamplePoint&) override {
    on_frame_(model_, state);
    shown_step_ = state.step;
  }
  void finish(const State& state, const DriveResult&) override {
    if (shown_step_ != state.step) on_frame_(model_, state);
  }

 private:
  const Model& model_;
  long long frame_every_;
  const FrameCallback& on_frame_;
  long long shown_step_ = -1;  // iteration of the last frame
};

}  // namespace

PanelRun run_panel(const Scene& scene, long long step_shown, long long frame_every,
                   const FrameCallback& on_frame) {
  PanelRun run;
  run.requested = step_shown;
  run.sim = build_simulation(scene);
  run.initial_x = run.sim.state.x;
  PanelFrames frames(run.sim.model, frame_every, on_frame);
  std::vector<RunObserver*> observers;
  if (on_frame) observers.push_back(&frames);
  DriveSpec spec;
  spec.steps = std::max<long long>(0, step_shown - run.sim.state.step);
  spec.end_on_last_good = true;  // after a divergence the panel shows the last good state
  const DriveResult result = drive(run.sim.model, run.sim.state, spec, observers);
  run.divergence = result.divergence;
  run.simulate_seconds = result.totals.wall_seconds;
  return run;
}

void fit_panel_camera(Renderer& renderer, const Model& model, const Vec3List& initial_x) {
  State first;
  first.x = initial_x;
  const FrameContent content = drawn_frame(model, first, mean_edge_length(model, initial_x));
  renderer.fit_camera(content_bounds(content), content.obstacles);
}

Image render_panel(const Scene& scene, const PanelRun& run, int width, int height) {
  Renderer renderer(still_render_settings(scene, width, height));
  fit_panel_camera(renderer, run.sim.model, run.initial_x);
  const double edge_length = mean_edge_length(run.sim.model, run.initial_x);
  renderer.draw(drawn_frame(run.sim.model, run.sim.state, edge_length));
  Image image(width, height);
  renderer.read_rgb(image.rgb);
  return image;
}

CaptionValues caption_values(const Scene& scene, const PanelRun& run, bool wall_time) {
  CaptionValues v;
  v.name = scene.name;
  v.triangles = run.sim.model.num_triangles();
  v.vertices = run.sim.model.num_vertices();
  v.step = run.sim.state.step;
  if (wall_time) v.wall_seconds = run.simulate_seconds;
  v.time = run.sim.state.t;
  v.integrator = integrator_name(run.sim.model.integrator);
  v.material = run.sim.model.material.name;
  v.dt = run.sim.model.dt;
  v.correction = run.sim.model.position_correction.has_value();
  return v;
}

std::string panel_caption(const std::string& caption_template, const Scene& scene,
                          const PanelRun& run, bool wall_time) {
  std::string caption = expand_caption(caption_template, caption_values(scene, run, wall_time));
  if (run.divergence) {
    caption += "\ndiverged at iteration " + std::to_string(run.divergence->step);
  }
  return caption;
}

}  // namespace tissu
