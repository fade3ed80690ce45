// How a run is rendered: plain settings, read from a scene's "render" block by
// view/render_block.h (docs/rendering.md lists every key).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/types.h"
#include "render/camera.h"

namespace tissu {

// Colours are [r, g, b] in 0..1 (display values, as in a colour picker).
struct Background {
  Vec3 top = Vec3(0.20, 0.25, 0.33);
  Vec3 bottom = Vec3(0.62, 0.66, 0.72);  // equal to top for a plain colour
};

struct Light {
  Vec3 direction = Vec3(0, 0, -1);  // direction the light travels (from the light into the scene)
  Vec3 color = Vec3::Ones();
  double intensity = 1.0;
};

enum class ClothPattern { Weave, Checker, None };

struct ClothLook {
  Vec3 front_color = Vec3(0.78, 0.20, 0.16);
  Vec3 back_color = Vec3(0.90, 0.78, 0.48);
  ClothPattern pattern = ClothPattern::Weave;
  double pattern_size = 0.1;  // m of rest (u, v) per repeat of the pattern
  bool wireframe = false;
  Vec3 wireframe_color = Vec3(0.08, 0.08, 0.08);
};

struct Ground {
  double height = 0.0;  // of the ground plane along RenderSettings::up (m): z with z up
  Vec3 color = Vec3(0.56, 0.56, 0.53);
  bool shadow = true;   // shadow of the cloth and obstacles from the first (key) light
};

constexpr int kMaxLights = 4;

struct RenderSettings {
  int width = 1280, height = 720;  // pixels, even
  int msaa = 4;                    // samples per pixel: 1, 2 or 4
  bool fxaa = false;               // single sample smoothed by FXAA (msaa 1, the default with it)
  int fps = 30;                    // video frames per second of video time
  double slow_motion = 1.0;        // video time = simulated time * slow_motion
  Background background;
  CameraSettings camera;            // eye/target absent = automatic framing
  std::vector<Light> lights = default_lights();
  ClothLook cloth;
  std::optional<Ground> ground;     // absent = no ground
  // Up for the camera, the ground and the default lights: render.up, else minus the
  // scene's gravity, else +z. Unit, in the scene's coordinates.
  Vec3 up = Vec3::UnitZ();
  std::string caption;              // drawn centred at the top; empty = none
  bool info = false;                // corner text: integrator, triangle count, time

  static std::vector<Light> default_lights();
};

}  // namespace tissu
