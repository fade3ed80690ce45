#include "figure/panel.h"

#include <sstream>

#include "physics/stepper.h"
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

PanelRun run_panel(const Scene& scene, long long step_shown, long long frame_every,
                   const FrameCallback& on_frame) {
  PanelRun run;
  run.requested = step_shown;
  run.sim = build_simulation(scene);
  const Model& model = run.sim.model;
  State& state = run.sim.state;
  run.initial_x = state.x;
  Stepper stepper(model, state);
  auto frame_due = [&](long long s) {
    return on_frame && (s == step_shown || (frame_every > 0 && s % frame_every == 0));
  };
  if (frame_due(0)) on_frame(model, state);
  while (state.step < step_shown) {
    // The state before the step is kept: after a divergence the panel shows it.
    const std::optional<Divergence> divergence = stepper.advance(true);
    if (divergence) {
      run.divergence = divergence;
      stepper.restore_before();
      if (on_frame && !frame_due(state.step)) on_frame(model, state);  // video ends on it
      break;
    }
    if (frame_due(state.step)) on_frame(model, state);
  }
  run.simulate_seconds = stepper.totals().wall_seconds;
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
