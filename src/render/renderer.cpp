#include "render/renderer.h"

#include <glm/gtc/matrix_inverse.hpp>

#include <cmath>

#include "render/cloth_geometry.h"
#include "render/obstacle_meshes.h"
#include "render/offscreen_context.h"
#include "render/render_error.h"
#include "render/scene_bounds.h"
#include "render/shader_files.h"
#include "render/shader_program.h"
#include "render/shadow_map.h"
#include "render/text_overlay.h"
#include "render/view_math.h"

namespace tissu {

namespace {

constexpr int kShadowMapSize = 1024;
const Vec3 kObstacleColor(0.60, 0.64, 0.70);
const Vec3 kPlaneColor(0.70, 0.70, 0.66);

// Scene colours are display values; lighting is done in linear light, with gamma 2
// (the shaders convert back with a square root).
glm::vec3 linear(const Vec3& display) {
  const glm::vec3 c = to_glm(display);
  return c * c;
}

int pattern_code(ClothPattern p) {
  switch (p) {
    case ClothPattern::Weave: return 1;
    case ClothPattern::Checker: return 2;
    case ClothPattern::None: default: return 0;
  }
}

ObstacleShape ground_plane(const Ground& ground) {
  ObstacleShape plane;
  plane.kind = ObstacleShape::Kind::Plane;
  plane.center = Vec3(0, 0, ground.height);
  plane.axis = Vec3::UnitZ();
  return plane;
}

}  // namespace

struct Renderer::Impl {
  Impl(const RenderSettings& s, const std::string& shader_dir)
      : settings(s),
        context(s.width, s.height, s.msaa),
        shader_dirs(shader_search_dirs(shader_dir)),
        background("background.vert", "background.frag", shader_dirs),
        cloth("cloth.vert", "cloth.frag", shader_dirs),
        shadow("shadow.vert", "shadow.frag", shader_dirs),
        solid("obstacle.vert", "obstacle.frag", shader_dirs),
        plane("obstacle.vert", "obstacle.frag", shader_dirs, {"PLANE"}),
        text(shader_dirs, s.width, s.height),
        empty_vao(make_vertex_array()) {
    sphere.upload(unit_sphere(64, 32));
    cylinder.upload(unit_cylinder(64));
    square.upload(unit_square());
    if (settings.ground && settings.ground->shadow) {
      shadow_map = std::make_unique<ShadowMap>(kShadowMapSize);
      ground = std::make_unique<ShaderProgram>("obstacle.vert", "obstacle.frag", shader_dirs,
                                               std::vector<std::string>{"PLANE", "RECEIVE_SHADOW"});
    }
    if (settings.camera.fixed()) {
      camera = Camera{*settings.camera.eye, *settings.camera.target, settings.camera.up,
                      settings.camera.fov_deg};
    }
    check_gl("renderer: setting up");
  }

  void draw(const FrameContent& content);
  void set_lights(const ShaderProgram& program) const;
  void draw_shadow_map(const FrameContent& content, const Box3& casters);
  void draw_background();
  void draw_plane(const ObstacleShape& shape, const Vec3& color, bool shadowed);
  void draw_obstacles(const FrameContent& content);
  void draw_cloth();

  double aspect() const { return static_cast<double>(settings.width) / settings.height; }
  // Half size of the squares that stand for planes: well past the framed scene.
  float plane_half_size() const {
    return static_cast<float>(4.0 * (camera->target - camera->eye).norm());
  }

  RenderSettings settings;
  OffscreenContext context;  // first: everything below lives in this context
  std::vector<std::string> shader_dirs;
  ShaderProgram background, cloth, shadow;
  ShaderProgram solid;                    // spheres and cylinders
  ShaderProgram plane;                    // plane obstacles, and the ground without shadow
  std::unique_ptr<ShaderProgram> ground;  // the ground receiving the key light's shadow
  TextOverlay text;
  GlVertexArray empty_vao;  // core profile draws need a bound vertex array
  MeshBuffer cloth_mesh, sphere, cylinder, square;
  std::unique_ptr<ShadowMap> shadow_map;
  std::optional<Camera> camera;
  std::vector<MeshVertex> corners;  // reused between frames
  glm::mat4 view_projection{1.0f};
  bool shadows_drawn = false;
  bool has_frame = false;
};

void Renderer::Impl::draw(const FrameContent& content) {
  context.make_current();
  check_cloth(content);
  std::optional<double> ground_height;
  if (settings.ground) ground_height = settings.ground->height;
  if (!camera) camera = auto_camera(content, aspect(), settings.camera, ground_height);

  // Depth range: everything drawn, planes as their squares.
  const Box3 bounds = content_bounds(content);
  std::vector<Vec3> extent = bounds.isEmpty() ? std::vector<Vec3>{} : box_corners(bounds);
  std::vector<ObstacleShape> planes;
  for (const ObstacleShape& o : content.obstacles) {
    if (o.kind == ObstacleShape::Kind::Plane) planes.push_back(o);
  }
  if (settings.ground) planes.push_back(ground_plane(*settings.ground));
  for (const ObstacleShape& shape : planes) {
    const glm::mat4 model = obstacle_model(shape, to_glm(camera->target), plane_half_size());
    for (const MeshVertex& v : unit_square().vertices) {
      const glm::vec4 p = model * glm::vec4(v.position, 1.0f);
      extent.emplace_back(p.x, p.y, p.z);
    }
  }
  if (extent.empty()) extent.push_back(camera->target);
  view_projection = projection_matrix(*camera, aspect(), extent) * view_matrix(*camera);

  cloth_corners(content, corners);
  cloth_mesh.upload_triangles(corners);

  shadows_drawn = false;
  if (shadow_map && !settings.lights.empty() && !bounds.isEmpty()) {
    draw_shadow_map(content, bounds);
  }
  context.bind_draw_target();
  glClearColor(0, 0, 0, 1);
  glClearDepth(1.0);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  draw_background();
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  // Front to back (roughly), so the depth test spares hidden fragments their shading.
  draw_cloth();
  draw_obstacles(content);
  if (settings.ground) draw_plane(ground_plane(*settings.ground), settings.ground->color, true);
  text.draw(settings.caption, content.overlay_lines);
  check_gl("renderer: drawing a frame");
  has_frame = true;
}

void Renderer::Impl::set_lights(const ShaderProgram& program) const {
  std::vector<glm::vec3> towards, radiance;
  for (const Light& light : settings.lights) {
    towards.push_back(-glm::normalize(to_glm(light.direction)));
    radiance.push_back(linear(light.color) * static_cast<float>(light.intensity));
  }
  program.set("u_light_count", static_cast<int>(settings.lights.size()));
  program.set("u_light_to", towards);
  program.set("u_light_radiance", radiance);
  program.set("u_eye", to_glm(camera->eye));
}

void Renderer::Impl::draw_shadow_map(const FrameContent& content, const Box3& casters) {
  shadow_map->begin(settings.lights[0].direction, casters);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  // Push casters slightly away from the light so cloth lying on the ground does not shadow it.
  glEnable(GL_POLYGON_OFFSET_FILL);
  glPolygonOffset(2.0f, 4.0f);
  shadow.use();
  shadow.set("u_light_matrix", shadow_map->light_matrix());
  shadow.set("u_model", glm::mat4(1.0f));
  cloth_mesh.draw();
  for (const ObstacleShape& o : content.obstacles) {
    if (o.kind == ObstacleShape::Kind::Plane) continue;
    shadow.set("u_model", obstacle_model(o, glm::vec3(0.0f), 0.0f));
    (o.kind == ObstacleShape::Kind::Sphere ? sphere : cylinder).draw();
  }
  glDisable(GL_POLYGON_OFFSET_FILL);
  shadows_drawn = true;
}

void Renderer::Impl::draw_background() {
  glDisable(GL_DEPTH_TEST);
  glDepthMask(GL_FALSE);
  background.use();
  background.set("u_top", to_glm(settings.background.top));
  background.set("u_bottom", to_glm(settings.background.bottom));
  background.set("u_height", static_cast<float>(settings.height));
  glBindVertexArray(empty_vao.get());
  glDrawArrays(GL_TRIANGLES, 0, 3);  // one triangle covering the screen
  glBindVertexArray(0);
  glDepthMask(GL_TRUE);
}

void Renderer::Impl::draw_plane(const ObstacleShape& shape, const Vec3& color, bool shadowed) {
  const float half = plane_half_size();
  const glm::mat4 model = obstacle_model(shape, to_glm(camera->target), half);
  const bool use_shadow = shadowed && shadows_drawn;
  const ShaderProgram& program = use_shadow ? *ground : plane;
  program.use();
  set_lights(program);
  program.set("u_view_projection", view_projection);
  program.set("u_model", model);
  program.set("u_normal_matrix", glm::inverseTranspose(glm::mat3(model)));
  program.set("u_albedo", linear(color));
  // Fade the square's edge into the background instead of showing a horizon line.
  program.set("u_fade_center", glm::vec3(model[3]));
  program.set("u_fade_radius", half);
  if (use_shadow) {
    program.set("u_shadow_map", 0);
    program.set("u_light_matrix", shadow_map->light_matrix());
    program.set("u_shadow_texel", 1.0f / static_cast<float>(shadow_map->size()));
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, shadow_map->texture());
  }
  glEnable(GL_BLEND);
  glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
  glEnable(GL_POLYGON_OFFSET_FILL);  // cloth resting on the plane stays in front
  glPolygonOffset(1.0f, 2.0f);
  square.draw();
  glDisable(GL_POLYGON_OFFSET_FILL);
  glDisable(GL_BLEND);
}

void Renderer::Impl::draw_obstacles(const FrameContent& content) {
  for (const ObstacleShape& o : content.obstacles) {
    if (o.kind == ObstacleShape::Kind::Plane) continue;
    const glm::mat4 model = obstacle_model(o, glm::vec3(0.0f), 0.0f);
    solid.use();
    set_lights(solid);
    solid.set("u_view_projection", view_projection);
    solid.set("u_model", model);
    solid.set("u_normal_matrix", glm::inverseTranspose(glm::mat3(model)));
    solid.set("u_albedo", linear(kObstacleColor));
    (o.kind == ObstacleShape::Kind::Sphere ? sphere : cylinder).draw();
  }
  // Planes last: they are blended at their fading edge.
  for (const ObstacleShape& o : content.obstacles) {
    if (o.kind == ObstacleShape::Kind::Plane) draw_plane(o, kPlaneColor, false);
  }
}

void Renderer::Impl::draw_cloth() {
  if (cloth_mesh.empty()) return;
  const ClothLook& look = settings.cloth;
  cloth.use();
  set_lights(cloth);
  cloth.set("u_view_projection", view_projection);
  cloth.set("u_front_color", linear(look.front_color));
  cloth.set("u_back_color", linear(look.back_color));
  cloth.set("u_pattern", pattern_code(look.pattern));
  cloth.set("u_pattern_size", static_cast<float>(look.pattern_size));
  cloth.set("u_wireframe", look.wireframe ? 1 : 0);
  cloth.set("u_wireframe_color", to_glm(look.wireframe_color));
  cloth_mesh.draw();
}

Renderer::Renderer(const RenderSettings& settings, const std::string& shader_dir_override)
    : impl_(std::make_unique<Impl>(settings, shader_dir_override)) {}

Renderer::~Renderer() {
  impl_->context.make_current();  // GL objects are deleted in their own context
}

void Renderer::set_camera(const Camera& camera) { impl_->camera = camera; }
const std::optional<Camera>& Renderer::camera() const { return impl_->camera; }

void Renderer::draw(const FrameContent& content) { impl_->draw(content); }

void Renderer::read_rgb(std::vector<uint8_t>& out) {
  if (!impl_->has_frame) throw RenderError("renderer: read_rgb() called before draw()");
  impl_->context.make_current();
  impl_->context.read_rgb(out);
}

int Renderer::width() const { return impl_->context.width(); }
int Renderer::height() const { return impl_->context.height(); }
int Renderer::samples() const { return impl_->context.samples(); }
std::string Renderer::gl_version() const {
  impl_->context.make_current();
  return impl_->context.gl_version();
}

}  // namespace tissu
