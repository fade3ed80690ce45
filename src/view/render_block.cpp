#include "view/render_block.h"

#include <cmath>

#include "render/up_axis.h"

namespace tissu {

namespace {

const Range kUnit = Range::between(0.0, 1.0);
constexpr long long kMinSize = 16, kMaxSize = 7680;  // image width and height, pixels

// An [r, g, b] colour in 0..1; `fallback` when the key is absent.
Vec3 read_color(JsonReader& r, const std::string& key, const Vec3& fallback) {
  r.accept(key);
  if (!r.has(key)) return fallback;
  const std::vector<double> c = r.numbers(key, 3, kUnit);
  return Vec3(c[0], c[1], c[2]);
}

Vec3 read_required_color(JsonReader& r, const std::string& key) {
  const std::vector<double> c = r.numbers(key, 3, kUnit);
  return Vec3(c[0], c[1], c[2]);
}

int read_even_size(JsonReader& r, const std::string& key, int fallback) {
  const long long value = r.integer(key, fallback, Range::any());
  if (value < kMinSize || value > kMaxSize) {
    throw InputError(r.path_of(key) + ": must be in [" + std::to_string(kMinSize) + ", " +
                     std::to_string(kMaxSize) + "] pixels, got " + std::to_string(value));
  }
  if (value % 2 != 0) {
    throw InputError(r.path_of(key) + ": must be even (video encoders need even sizes), got " +
                     std::to_string(value));
  }
  return static_cast<int>(value);
}

Vec3 read_nonzero_direction(JsonReader& r, const std::string& key, const Vec3& fallback) {
  const Vec3 v = r.vec3(key, fallback);
  if (v.norm() < 1e-12) throw InputError(r.path_of(key) + ": must not be the zero vector");
  return v;
}

Background read_background(JsonReader& r) {
  const std::string key = "background";
  r.accept(key);
  Background background;
  if (!r.has(key)) return background;
  const Json& value = r.raw(key);
  if (value.is_object()) {
    JsonReader gradient(value, r.path_of(key));
    background.top = read_required_color(gradient, "top");
    background.bottom = read_required_color(gradient, "bottom");
    gradient.finish();
  } else if (value.is_array()) {
    background.top = background.bottom = read_required_color(r, key);
  } else {
    throw InputError(r.path_of(key) +
                     ": must be a colour [r, g, b] or a gradient {\"top\": [r, g, b], "
                     "\"bottom\": [r, g, b]}");
  }
  return background;
}

CameraSettings read_camera(JsonReader& r, const Vec3& up) {
  CameraSettings camera;
  camera.up = up;
  r.accept("camera");
  if (!r.has("camera")) return camera;
  JsonReader c = r.object("camera");
  if (c.has("eye")) camera.eye = c.vec3("eye");
  if (c.has("target")) camera.target = c.vec3("target");
  c.accept("eye");
  c.accept("target");
  camera.up = read_nonzero_direction(c, "up", camera.up);
  camera.fov_deg = c.number("fov", camera.fov_deg, Range{0.0, 170.0, true, false});
  camera.framing = c.choice("framing", {"run", "first"}, "run") == "run" ? Framing::Run : Framing::First;
  c.finish();
  if (camera.fixed()) {
    const Vec3 view = *camera.target - *camera.eye;
    if (view.norm() < 1e-9) {
      throw InputError(c.path_of("target") + ": must differ from camera.eye");
    }
    if (view.normalized().cross(camera.up.normalized()).norm() < 1e-6) {
      throw InputError(c.path_of("up") + ": must not be parallel to the view direction");
    }
  }
  return camera;
}

std::vector<Light> read_lights(JsonReader& r, const Vec3& up) {
  r.accept("lights");
  if (!r.has("lights")) {  // placed for z up: turned to the scene's up
    std::vector<Light> lights = RenderSettings::default_lights();
    const Mat3 to_scene = rotation_up_to_z(up).transpose();
    for (Light& light : lights) light.direction = to_scene * light.direction;
    return lights;
  }
  const Json& list = r.raw("lights");
  const std::string path = r.path_of("lights");
  if (!list.is_array()) throw InputError(path + ": must be an array of light objects");
  if (list.size() > static_cast<size_t>(kMaxLights)) {
    throw InputError(path + ": at most " + std::to_string(kMaxLights) + " lights, got " +
                     std::to_string(list.size()));
  }
  std::vector<Light> lights;
  for (size_t i = 0; i < list.size(); ++i) {
    JsonReader l(list[i], element_path(path, i));
    Light light;
    light.direction = read_nonzero_direction(l, "direction", light.direction);
    light.color = read_color(l, "color", light.color);
    light.intensity = l.number("intensity", light.intensity, Range::between(0.0, 100.0));
    l.finish();
    lights.push_back(light);
  }
  return lights;
}

ClothLook read_cloth(JsonReader& r) {
  ClothLook look;
  r.accept("cloth");
  if (!r.has("cloth")) return look;
  JsonReader c = r.object("cloth");
  look.front_color = read_color(c, "front_color", look.front_color);
  look.back_color = read_color(c, "back_color", look.back_color);
  const std::string pattern = c.choice("pattern", {"weave", "checker", "none"}, "weave");
  look.pattern = pattern == "weave"     ? ClothPattern::Weave
                 : pattern == "checker" ? ClothPattern::Checker
                                        : ClothPattern::None;
  look.pattern_size = c.number("pattern_size", look.pattern_size, Range::positive());
  look.wireframe = c.boolean("wireframe", look.wireframe);
  look.wireframe_color = read_color(c, "wireframe_color", look.wireframe_color);
  c.finish();
  return look;
}

std::optional<Ground> read_ground(JsonReader& r) {
  r.accept("ground");
  if (!r.has("ground")) return std::nullopt;
  JsonReader g = r.object("ground");
  Ground ground;
  ground.height = g.number("height", ground.height);
  ground.color = read_color(g, "color", ground.color);
  ground.shadow = g.boolean("shadow", ground.shadow);
  g.finish();
  return ground;
}

}  // namespace

Vec3 up_from_gravity(const std::optional<Vec3>& gravity) {
  if (!gravity || gravity->norm() < 1e-12) return Vec3::UnitZ();
  return -gravity->normalized();
}

RenderSettings parse_render_settings(JsonReader& render, const Vec3& scene_up) {
  RenderSettings s;
  s.up = read_nonzero_direction(render, "up", scene_up).normalized();
  s.width = read_even_size(render, "width", s.width);
  s.height = read_even_size(render, "height", s.height);
  s.msaa = static_cast<int>(render.integer("msaa", s.msaa, Range::any()));
  if (s.msaa != 1 && s.msaa != 2 && s.msaa != 4) {
    throw InputError(render.path_of("msaa") + ": must be 1, 2 or 4, got " +
                     std::to_string(s.msaa));
  }
  s.fxaa = render.boolean("fxaa", s.fxaa);
  if (s.fxaa && !render.has("msaa")) s.msaa = 1;
  if (s.fxaa && s.msaa != 1) {
    throw InputError(render.path_of("fxaa") + ": needs render.msaa 1 (FXAA replaces multisampling), got msaa " +
                     std::to_string(s.msaa));
  }
  s.fps = static_cast<int>(render.integer("fps", s.fps, Range::any()));
  if (s.fps < 1 || s.fps > 240) {
    throw InputError(render.path_of("fps") + ": must be in [1, 240], got " +
                     std::to_string(s.fps));
  }
  s.slow_motion = render.number("slow_motion", s.slow_motion, Range{1.0, 1e300, false, false});
  s.background = read_background(render);
  s.camera = read_camera(render, s.up);
  s.lights = read_lights(render, s.up);
  s.cloth = read_cloth(render);
  s.ground = read_ground(render);
  s.caption = render.string("caption", s.caption);
  s.info = render.boolean("info", s.info);
  render.finish();
  return s;
}

}  // namespace tissu
