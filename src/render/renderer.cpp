#include "render/renderer.h"

#include <glm/gtc/matrix_inverse.hpp>

#include <cmath>
#include <map>

#include "render/draw/cloth_geometry.h"
#include "render/draw/ground_geometry.h"
#include "render/draw/obstacle_meshes.h"
#include "render/draw/view_math.h"
#include "render/gl/offscreen_context.h"
#include "render/gl/pass_timer.h"
#include "render/gl/shader_files.h"
#include "render/gl/shader_program.h"
#include "render/image/fxaa.h"
#include "render/image/text_overlay.h"
#include "render/render_error.h"
#include "render/scene_bounds.h"
#include "render/up_axis.h"

namespace tissu {

namespace {

const Vec3 kObstacleColor(0.60, 0.64, 0.70);
const Vec3 kPlaneColor(0.70, 0.70, 0.66);
// A plane obstacle this close to the ground (same side up) is drawn as part of the ground.
constexpr double kGroundMergeDistance = 0.01;  // m
// Spheres are drawn with kSphereSlices around (and half as many stacks), or with
// kSmallSphereSlices when they look small enough that the flats along their outline stay
// within kSphereOutlineError pixels of the true circle (fewer triangles: each costs on
// llvmpipe). The ground's shadow always uses the finer sphere.
constexpr int kSphereSlices = 64;
constexpr int kSmallSphereSlices = 48;
constexpr double kSphereOutlineError = 0.35;  // pixels

// Planes fade out from this fraction of their half size (obstacle.frag: smoothstep(0.45, ...)).
constexpr double kGroundFadeStart = 0.45;
// The ground's grid: cells entirely inside the fade's start are drawn with the cheaper
// opaque shader; the finer the grid, the closer they come to the fade.
constexpr int kGroundDivisions = 16;
// The opaque disc's radius, over the ground's half size: slightly inside the fade's start,
// so that rounding cannot put a faded pixel in an opaque cell.
constexpr double kGroundOpaqueRadius = 0.999 * kGroundFadeStart;
// When those cells are cleared instead of drawn, the ground is a ring of quads around a
// polygon of this many sides (and the corners' rays) inscribed in the opaque disc: between
// it and the disc's edge lies a band 0.12% of its radius wide.
constexpr int kGroundRingSides = 64;

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

// The ground's shadow clips what is under the ground and what falls off its square.
constexpr int kShadowClipPlanes = 5;

// Shader variant defines for the lit programs.
std::vector<std::string> lit_defines(const RenderSettings& s, std::vector<std::string> more = {}) {
  more.push_back("LIGHT_COUNT " + std::to_string(s.lights.size()));
  return more;
}

std::vector<std::string> cloth_defines(const RenderSettings& s) {
  std::vector<std::string> d = {"PATTERN " + std::to_string(pattern_code(s.cloth.pattern))};
  if (s.cloth.wireframe) d.push_back("WIREFRAME");
  return lit_defines(s, d);
}

// The ground, or (CAST_SHADOW) the key light's shadow on it; OPAQUE where it does not fade.
std::vector<std::string> ground_defines(const RenderSettings& s, bool shadow, bool opaque) {
  std::vector<std::string> d = {"PLANE", "GROUND"};
  if (shadow) d.push_back("CAST_SHADOW");
  if (opaque) d.push_back("OPAQUE");
  return lit_defines(s, d);
}

// Along `direction` (downwards) onto the plane z = height: the shadow of a point there.
glm::mat4 flatten_onto_ground(const Vec3& direction, double height) {
  const Vec3 d = direction.normalized();
  glm::mat4 m(1.0f);  // glm: m[column][row]
  m[2][0] = static_cast<float>(-d.x() / d.z());
  m[2][1] = static_cast<float>(-d.y() / d.z());
  m[2][2] = 0.0f;
  m[3][0] = static_cast<float>(height * d.x() / d.z());
  m[3][1] = static_cast<float>(height * d.y() / d.z());
  m[3][2] = static_cast<float>(height);
  return m;
}

}  // namespace

struct Renderer::Impl {
  Impl(const RenderSettings& s, const std::string& shader_dir)
      : settings(s),
        context(s.width, s.height, s.msaa),
        shader_dirs(shader_search_dirs(shader_dir)),
        background("background.vert", "background.frag", shader_dirs),
        cloth("cloth.vert", "cloth.frag", shader_dirs, cloth_defines(s)),
        solid("obstacle.vert", "obstacle.frag", shader_dirs, lit_defines(s)),
        plane("obstacle.vert", "obstacle.frag", shader_dirs, lit_defines(s, {"PLANE"})),
        text(s.width, s.height),
        background_vao(make_vertex_array()),
        background_vertices(make_buffer()) {
    glBindVertexArray(background_vao.get());
    glBindBuffer(GL_ARRAY_BUFFER, background_vertices.get());
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, sizeof(glm::vec2), nullptr);
    glBindVertexArray(0);
    sphere.upload(unit_sphere(kSphereSlices, kSphereSlices / 2));
    small_sphere.upload(unit_sphere(kSmallSphereSlices, kSmallSphereSlices / 2));
    cylinder.upload(unit_cylinder(64));
    square.upload(unit_square());
    if (settings.ground) {
      auto ground_program = [&](bool shadow, bool opaque) {
        return std::make_unique<ShaderProgram>("obstacle.vert", "obstacle.frag", shader_dirs,
                                               ground_defines(s, shadow, opaque));
      };
      ground = ground_program(false, false);
      ground_opaque = ground_program(false, true);
      if (settings.ground->shadow) {
        ground_shadow = ground_program(true, false);
        ground_shadow_opaque = ground_program(true, true);
      }
    }
    if (settings.camera.fixed()) {
      camera = Camera{*settings.camera.eye, *settings.camera.target, settings.camera.up,
                      settings.camera.fov_deg};
    }
    check_gl("renderer: setting up");
  }

  void draw(const FrameContent& content);
  void set_lights(const ShaderProgram& program) const;
  void upload_cloth(const FrameContent& content);
  void draw_cloth_geometry() const;
  void gather_caster_points(const FrameContent& content);
  bool reaches_under_ground(double height) const;
  void draw_background(bool ground_drawn);
  void set_plane_uniforms(const ShaderProgram& program, const glm::mat4& model, const Vec3& color);
  void draw_plane(const ObstacleShape& shape, const Vec3& color);
  void draw_ground(const ObstacleShape* merged_plane, bool depth_needed_later, bool opaque_cleared);
  void draw_ground_shadow(const FrameContent& content, const ObstacleShape* merged_plane);
  GroundRect ground_square() const;
  // Radius of the disc where the ground does not fade (m).
  double ground_opaque_radius() const { return kGroundOpaqueRadius * plane_half_size(); }
  void set_ground_uniforms(const ShaderProgram& program, const ObstacleShape* merged_plane);
  glm::vec3 lit_ground_color() const;
  void draw_solids(const FrameContent& content);
  void draw_cloth();
  const ObstacleShape* plane_merged_into_ground(const FrameContent& content) const;
  const MeshBuffer& sphere_for_view(const ObstacleShape& shape) const;
  const MeshBuffer& buffer_of(const ObstacleShape& shape);

  double aspect() const { return static_cast<double>(settings.width) / settings.height; }
  std::optional<double> ground_height() const {
    return settings.ground ? std::optional<double>(settings.ground->height) : std::nullopt;
  }
  // Half size of the squares that stand for planes: well past the framed scene.
  float plane_half_size() const {
    return static_cast<float>(4.0 * (camera->target - camera->eye).norm());
  }

  RenderSettings settings;
  OffscreenContext context;  // first: everything below lives in this context
  std::vector<std::string> shader_dirs;
  ShaderProgram background, cloth;
  ShaderProgram solid;  // spheres and cylinders
  ShaderProgram plane;  // plane obstacles (blended at their fading edge)
  // The ground, and the key light's shadow on it, where it fades and where it does not.
  std::unique_ptr<ShaderProgram> ground, ground_opaque;
  std::unique_ptr<ShaderProgram> ground_shadow, ground_shadow_opaque;
  TextOverlay text;
  std::vector<std::string> overlay_lines;  // the last frame's corner text
  GlVertexArray background_vao;
  GlBuffer background_vertices;
  MeshBuffer cloth_corners_mesh, sphere, small_sphere, cylinder, square;
  MeshBuffer ground_fading, ground_opaque_mesh;  // parts of the ground (see SplitGround)
  std::vector<Vec3> caster_points;  // their convex hull holds every caster this frame
  std::vector<glm::vec4> ground_outline;  // clip space, this frame
  ClothBuffer cloth_mesh;
  // Mesh obstacles' surfaces, uploaded once (the key keeps the surface alive).
  std::map<std::shared_ptr<const Vec3List>, std::unique_ptr<MeshBuffer>> surfaces;
  std::optional<Camera> camera;
  // From the scene's coordinates to the renderer's (z up); `settings` are already turned.
  Mat3 to_render = Mat3::Identity();
  bool turning = false;
  FrameContent turned_content;  // the frame in the renderer's coordinates, when turning
  FxaaScratch fxaa_scratch;
  // Reused between frames.
  std::vector<MeshVertex> corners;
  std::vector<ClothVertex> vertices;
  TriList triangles_uploaded;
  Vec2List uv_uploaded;
  std::vector<uint32_t> indices;
  std::vector<glm::vec2> uv;
  glm::mat4 view_projection{1.0f};
  bool has_frame = false;
  PassTimer timer;
};

void Renderer::Impl::draw(const FrameContent& content) {
  context.make_current();
  timer.start();
  check_cloth(content);
  if (!camera) camera = auto_camera(content, aspect(), settings.camera, ground_height());

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

  upload_cloth(content);
  gather_caster_points(content);
  const ObstacleShape* merged = plane_merged_into_ground(content);
  bool planes_later = false;  // plane obstacles drawn after the ground, depth-tested against it
  for (const ObstacleShape& o : content.obstacles) {
    if (o.kind == ObstacleShape::Kind::Plane && &o != merged) planes_later = true;
  }
  // The ground's opaque cells are one flat colour (seen from above): a clear to
  // it fills them for a fraction of the cost of shading them, so they are not drawn. When
  // plane obstacles follow, those cells must write depth, and are drawn as before; so they
  // are when something reaches under the ground, which they must hide.
  const bool ground_cleared = settings.ground && camera->eye.z() > settings.ground->height &&
                              !planes_later && !reaches_under_ground(settings.ground->height);
  context.bind_draw_target();
  // Every other sample gets a colour below (the background fills what nothing covers).
  glClearDepth(1.0);
  if (ground_cleared) {
    const glm::vec3 c = lit_ground_color();
    glClearColor(c.r, c.g, c.b, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  } else {
    glClear(GL_DEPTH_BUFFER_BIT);
  }
  timer.lap("clear");
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  // Opaque surfaces front to back (roughly), so the depth test spares hidden fragments
  // their shading; then the background behind all of them; then what is blended.
  draw_cloth();
  timer.lap("cloth");
  draw_solids(content);
  timer.lap("spheres and cylinders");
  if (settings.ground) draw_ground(merged, planes_later, ground_cleared);
  timer.lap("ground");
  if (ground_shadow && !settings.lights.empty() && !bounds.isEmpty()) {
    draw_ground_shadow(content, merged);
    timer.lap("ground shadow");
  }
  draw_background(settings.ground.has_value());
  timer.lap("background");
  for (const ObstacleShape& o : content.obstacles) {
    if (o.kind == ObstacleShape::Kind::Plane && &o != merged) draw_plane(o, kPlaneColor);
  }
  timer.lap("planes");
  overlay_lines = content.overlay_lines;  // blended in after the read-back
  check_gl("renderer: drawing a frame");
  has_frame = true;
}

void Renderer::Impl::upload_cloth(const FrameContent& content) {
  if (settings.cloth.wireframe) {
    cloth_corners(content, corners);
    timer.lap("cloth normals (CPU)");
    cloth_corners_mesh.upload_triangles(corners);
  } else {
    cloth_vertices(content, vertices);
    timer.lap("cloth normals (CPU)");
    if (content.triangles != triangles_uploaded || content.rest_uv != uv_uploaded) {
      cloth_topology(content, indices, uv);
      cloth_mesh.set_topology(indices, uv);
      triangles_uploaded = content.triangles;
      uv_uploaded = content.rest_uv;
    }
    cloth_mesh.upload_vertices(vertices);
  }
  timer.lap("cloth upload");
}

void Renderer::Impl::draw_cloth_geometry() const {
  if (settings.cloth.wireframe) {
    cloth_corners_mesh.draw();
  } else {
    cloth_mesh.draw();
  }
}

void Renderer::Impl::set_lights(const ShaderProgram& program) const {
  std::vector<glm::vec3> towards, radiance;
  for (const Light& light : settings.lights) {
    towards.push_back(-glm::normalize(to_glm(light.direction)));
    radiance.push_back(linear(light.color) * static_cast<float>(light.intensity));
  }
  program.set("u_light_to", towards);
  program.set("u_light_radiance", radiance);
  program.set("u_eye", to_glm(camera->eye));
}

// The cloth's vertices and the corners of each finite obstacle's box: the ground's shadow
// falls within the shadow of their convex hull, often much less ground than the shadow of
// all the casters' common box.
void Renderer::Impl::gather_caster_points(const FrameContent& content) {
  caster_points.clear();
  for (const Vec3& p : content.positions) {
    if (p.allFinite()) caster_points.push_back(p);
  }
  for (const ObstacleShape& o : content.obstacles) {
    const Box3 box = shown_bounds({}, {o});
    if (box.isEmpty()) continue;
    for (const Vec3& corner : box_corners(box)) caster_points.push_back(corner);
  }
}

// Whether a caster's points (the cloth's vertices, the obstacles' box corners) lie under
// the ground by more than a rounding error: a sphere resting on it does not.
bool Renderer::Impl::reaches_under_ground(double height) const {
  constexpr double kTolerance = 1e-6;  // m
  for (const Vec3& p : caster_points) {
    if (p.z() < height - kTolerance) return true;
  }
  return false;
}

void Renderer::Impl::draw_background(bool ground_drawn) {
  // Where the ground is drawn it already shows the background at its fading edge: cover
  // only the rest (overlapping the ground's outline by 2 pixels; the depth test sorts it out).
  const std::vector<glm::vec2> triangles =
      ground_drawn ? outside_of_polygon(ground_outline, settings.width, settings.height, 2.0)
                   : outside_of_polygon({}, settings.width, settings.height, 0.0);
  if (triangles.empty()) return;
  // At the far end of the depth range: only samples nothing else covered pass.
  glDepthFunc(GL_LEQUAL);
  glDepthMask(GL_FALSE);
  background.use();
  background.set("u_top", to_glm(settings.background.top));
  background.set("u_bottom", to_glm(settings.background.bottom));
  background.set("u_height", static_cast<float>(settings.height));
  glBindBuffer(GL_ARRAY_BUFFER, background_vertices.get());
  glBufferData(GL_ARRAY_BUFFER, triangles.size() * sizeof(glm::vec2), triangles.data(),
               GL_STREAM_DRAW);
  glBindVertexArray(background_vao.get());
  glDrawArrays(GL_TRIANGLES, 0, static_cast<GLsizei>(triangles.size()));
  glBindVertexArray(0);
  glDepthMask(GL_TRUE);
  glDepthFunc(GL_LESS);
}

void Renderer::Impl::set_plane_uniforms(const ShaderProgram& program, const glm::mat4& model,
                                        const Vec3& color) {
  program.use();
  set_lights(program);
  program.set("u_view_projection", view_projection);
  program.set("u_model", model);
  program.set("u_normal_matrix", glm::inverseTranspose(glm::mat3(model)));
  program.set("u_albedo", linear(color));
  // Fade the square's edge into the background instead of showing a horizon line.
  program.set("u_fade_center", glm::vec3(model[3]));
  program.set("u_fade_radius", plane_half_size());
}

void Renderer::Impl::draw_plane(const ObstacleShape& shape, const Vec3& color) {
  const glm::mat4 model = obstacle_model(shape, to_glm(camera->target), plane_half_size());
  set_plane_uniforms(plane, model, color);
  glEnable(GL_BLEND);
  glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
  glEnable(GL_POLYGON_OFFSET_FILL);  // cloth resting on the plane stays in front
  glPolygonOffset(1.0f, 2.0f);
  square.draw();
  glDisable(GL_POLYGON_OFFSET_FILL);
  glDisable(GL_BLEND);
}

// A plane obstacle lying in the ground (facing up, at most kGroundMergeDistance below or
// above it, seen from above) is hidden by the ground except where the ground fades out;
// the ground shader composites it there, so it is not drawn on its own.
const ObstacleShape* Renderer::Impl::plane_merged_into_ground(const FrameContent& content) const {
  if (!settings.ground || camera->eye.z() <= settings.ground->height) return nullptr;
  for (const ObstacleShape& o : content.obstacles) {
    if (o.kind != ObstacleShape::Kind::Plane || o.axis.norm() == 0.0) continue;
    const Vec3 n = o.axis.normalized();
    if (n.z() > 1.0 - 1e-12 && std::abs(o.center.z() - settings.ground->height) <= kGroundMergeDistance) {
      return &o;
    }
  }
  return nullptr;
}

// The display colour of the ground's front in full light: obstacle.vert's v_front_lit for
// the normal +z (lighting.glsl's shade() without highlight) through to_display(), in the
// same single-precision steps, so that a clear to it writes the bytes the shader writes.
glm::vec3 Renderer::Impl::lit_ground_color() const {
  const glm::vec3 albedo = linear(settings.ground->color);
  glm::vec3 color = albedo * glm::vec3(0.075f, 0.080f, 0.090f);  // the sky ambient at n.z = 1
  for (const Light& light : settings.lights) {
    const float diffuse = std::max(-glm::normalize(to_glm(light.direction)).z, 0.0f);
    color += linear(light.color) * static_cast<float>(light.intensity) * (albedo * diffuse);
  }
  return glm::sqrt(glm::clamp(color, 0.0f, 1.0f));
}

GroundRect Renderer::Impl::ground_square() const {
  // Centred below the camera target, as obstacle_model places planes.
  const double half = plane_half_size();
  const glm::dvec2 centre(camera->target.x(), camera->target.y());
  return GroundRect{centre - glm::dvec2(half), centre + glm::dvec2(half)};
}

void Renderer::Impl::set_ground_uniforms(const ShaderProgram& program, const ObstacleShape* merged_plane) {
  set_plane_uniforms(program, glm::mat4(1.0f), settings.ground->color);  // meshes in world coordinates
  const glm::mat4 placement = obstacle_model(ground_plane(*settings.ground),
                                             to_glm(camera->target), plane_half_size());
  program.set("u_fade_center", glm::vec3(placement[3]));
  program.set("u_top", to_glm(settings.background.top));
  program.set("u_bottom", to_glm(settings.background.bottom));
  program.set("u_height", static_cast<float>(settings.height));
  program.set("u_under", merged_plane ? 1.0f : 0.0f);
  program.set("u_under_albedo", linear(kPlaneColor));
}

void Renderer::Impl::draw_ground(const ObstacleShape* merged_plane, bool depth_needed_later,
                                 bool opaque_cleared) {
  const double h = settings.ground->height;
  const GroundRect square = ground_square();
  const glm::dvec2 centre = 0.5 * (square.min + square.max);
  ground_outline.clear();
  for (const glm::dvec2& corner : {square.min, glm::dvec2(square.max.x, square.min.y), square.max,
                                   glm::dvec2(square.min.x, square.max.y)}) {
    ground_outline.push_back(view_projection * glm::vec4(static_cast<float>(corner.x),
                                                         static_cast<float>(corner.y),
                                                         static_cast<float>(h), 1.0f));
  }
  auto draw_part = [&](const ShaderProgram& program, MeshBuffer& mesh, const IndexedMesh& part) {
    if (part.indices.empty()) return;
    set_ground_uniforms(program, merged_plane);
    mesh.upload(part);
    mesh.draw();
  };
  glEnable(GL_POLYGON_OFFSET_FILL);  // cloth resting on the ground stays in front
  glPolygonOffset(1.0f, 2.0f);
  // The fading part writes depth: the background, drawn next, overlaps its outer edge and
  // must stay behind it. The opaque cells need to write it only for plane obstacles drawn
  // later (the shadow, drawn next, needs only the depth of what is in front of the
  // ground): writing depth costs on every sample.
  // When the opaque disc was cleared to its colour, the fading part is a ring around it.
  const double opaque_radius = ground_opaque_radius();
  std::optional<IndexedMesh> ring;
  if (opaque_cleared) ring = ground_ring(square, h, centre, opaque_radius, kGroundRingSides);
  if (ring) {
    draw_part(*ground, ground_fading, *ring);
  } else {
    const SplitGround split = split_ground(square, h, centre, opaque_radius, kGroundDivisions);
    draw_part(*ground, ground_fading, split.fading);
    if (!depth_needed_later) glDepthMask(GL_FALSE);
    if (!opaque_cleared) draw_part(*ground_opaque, ground_opaque_mesh, split.opaque);
  }
  glDepthMask(GL_TRUE);
  glDisable(GL_POLYGON_OFFSET_FILL);
}

// The key light's shadow on the ground: the casters drawn flattened onto it along the light,
// in the ground's colour without that light. Only what is above the ground casts, and only
// onto its square (clip distances). It is exact, as sharp as the light is, and anti-aliased
// with the rest of the frame; it costs the casters' triangles and the shadow's pixels.
void Renderer::Impl::draw_ground_shadow(const FrameContent& content, const ObstacleShape* merged_plane) {
  const Vec3& direction = settings.lights[0].direction;
  const double h = settings.ground->height;
  // A light from below or level casts nothing on the ground's top; from below the ground
  // its top is not seen.
  if (!(direction.normalized().z() < -1e-6) || camera->eye.z() <= h) return;
  const GroundRect square = ground_square();
  const glm::dvec2 centre = 0.5 * (square.min + square.max);
  // Where the shadow cannot reach the fade, the flat shadowed colour is written.
  const std::optional<GroundRect> footprint = shadow_footprint(caster_points, direction, h, 0.0);
  const bool opaque = footprint && rect_within_disc(*footprint, centre, ground_opaque_radius());
  const ShaderProgram& program = opaque ? *ground_shadow_opaque : *ground_shadow;
  set_ground_uniforms(program, merged_plane);
  program.set("u_shadow_projection", flatten_onto_ground(direction, h));
  program.set("u_ground_height", static_cast<float>(h));
  program.set("u_ground_square", glm::vec4(static_cast<float>(square.min.x), static_cast<float>(square.min.y),
                                           static_cast<float>(square.max.x), static_cast<float>(square.max.y)));
  for (int i = 0; i < kShadowClipPlanes; ++i) glEnable(GL_CLIP_DISTANCE0 + i);
  // In front of the ground (drawn with offset 1, 2), behind cloth lying on it; overlapping
  // casters write the same colour, so no depth is written.
  glEnable(GL_POLYGON_OFFSET_FILL);
  glPolygonOffset(0.5f, 1.0f);
  glDepthMask(GL_FALSE);
  draw_cloth_geometry();
  // Spheres and cylinders are closed: their sides facing the light make the whole shadow,
  // and flattened they still face the camera above the ground.
  glEnable(GL_CULL_FACE);
  glCullFace(GL_BACK);
  for (const ObstacleShape& o : content.obstacles) {
    if (o.kind == ObstacleShape::Kind::Plane) continue;
    program.set("u_model", obstacle_model(o, glm::vec3(0.0f), 0.0f));
    buffer_of(o).draw();
  }
  glDisable(GL_CULL_FACE);
  glDepthMask(GL_TRUE);
  glDisable(GL_POLYGON_OFFSET_FILL);
  for (int i = 0; i < kShadowClipPlanes; ++i) glDisable(GL_CLIP_DISTANCE0 + i);
}

void Renderer::Impl::draw_solids(const FrameContent& content) {
  bool first = true;
  for (const ObstacleShape& o : content.obstacles) {
    if (o.kind == ObstacleShape::Kind::Plane) continue;
    if (first) {
      solid.use();
      set_lights(solid);
      solid.set("u_view_projection", view_projection);
      solid.set("u_albedo", linear(kObstacleColor));
      // Closed surfaces: the far side is always hidden by the near side.
      glEnable(GL_CULL_FACE);
      glCullFace(GL_BACK);
      first = false;
    }
    const glm::mat4 model = obstacle_model(o, glm::vec3(0.0f), 0.0f);
    solid.set("u_model", model);
    solid.set("u_normal_matrix", glm::inverseTranspose(glm::mat3(model)));
    (o.kind == ObstacleShape::Kind::Sphere ? sphere_for_view(o) : buffer_of(o)).draw();
  }
  glDisable(GL_CULL_FACE);
}

// The shape's own geometry: the unit sphere or cylinder, or the mesh's surface.
const MeshBuffer& Renderer::Impl::buffer_of(const ObstacleShape& shape) {
  if (shape.kind == ObstacleShape::Kind::Sphere) return sphere;
  if (shape.kind != ObstacleShape::Kind::Mesh) return cylinder;
  std::unique_ptr<MeshBuffer>& buffer = surfaces[shape.mesh_vertices];
  if (!buffer) {
    buffer = std::make_unique<MeshBuffer>();
    buffer->upload(surface_mesh(*shape.mesh_vertices, *shape.mesh_triangles));
  }
  return *buffer;
}

// The coarser sphere when its outline, seen from the camera, would be at most
// kSphereOutlineError pixels inside the true circle (a polygon of n sides inscribed in a
// circle of radius R pixels falls short of it by R (1 - cos(pi / n))).
const MeshBuffer& Renderer::Impl::sphere_for_view(const ObstacleShape& shape) const {
  const double distance = (shape.center - camera->eye).norm();
  if (!(distance > shape.radius)) return sphere;
  const double half_angle = std::asin(shape.radius / distance);
  const double tan_half_fov = std::tan(0.5 * camera->fov_deg * M_PI / 180.0);
  const double radius_pixels = 0.5 * settings.height * std::tan(half_angle) / tan_half_fov;
  const double shortfall = radius_pixels * (1.0 - std::cos(M_PI / kSmallSphereSlices));
  return shortfall <= kSphereOutlineError ? small_sphere : sphere;
}

void Renderer::Impl::draw_cloth() {
  if (settings.cloth.wireframe ? cloth_corners_mesh.empty() : cloth_mesh.empty()) return;
  const ClothLook& look = settings.cloth;
  cloth.use();
  set_lights(cloth);
  cloth.set("u_view_projection", view_projection);
  cloth.set("u_front_color", linear(look.front_color));
  cloth.set("u_back_color", linear(look.back_color));
  cloth.set("u_cells_per_m", static_cast<float>(2.0 / look.pattern_size));
  cloth.set("u_wireframe_color", to_glm(look.wireframe_color));
  draw_cloth_geometry();
}

Renderer::Renderer(const RenderSettings& settings, const std::string& shader_dir_override) {
  const Mat3 to_render = rotation_up_to_z(settings.up);
  impl_ = std::make_unique<Impl>(turned(settings, to_render), shader_dir_override);
  impl_->to_render = to_render;
  impl_->turning = !is_identity(to_render);
}

Renderer::~Renderer() {
  impl_->context.make_current();  // GL objects are deleted in their own context
}

void Renderer::set_camera(const Camera& camera) { impl_->camera = turned(camera, impl_->to_render); }

std::optional<Camera> Renderer::camera() const {
  if (!impl_->camera) return std::nullopt;
  return turned(*impl_->camera, impl_->to_render.transpose());
}

void Renderer::fit_camera(const Box3& shown, const std::vector<ObstacleShape>& obstacles) {
  Box3 box;
  if (!shown.isEmpty()) {
    for (const Vec3& corner : box_corners(shown)) box.extend(impl_->to_render * corner);
  }
  std::vector<ObstacleShape> planes;
  for (const ObstacleShape& o : obstacles) {
    if (o.kind == ObstacleShape::Kind::Plane) planes.push_back(turned(o, impl_->to_render));
  }
  impl_->camera =
      auto_camera(box, planes, impl_->aspect(), impl_->settings.camera, impl_->ground_height());
}

void Renderer::draw(const FrameContent& content) {
  if (!impl_->turning) return impl_->draw(content);
  turn_content(content, impl_->to_render, impl_->turned_content);
  impl_->draw(impl_->turned_content);
}

void Renderer::read_rgb(std::vector<uint8_t>& out) {
  if (!impl_->has_frame) throw RenderError("renderer: read_rgb() called before draw()");
  impl_->context.make_current();
  impl_->timer.start();
  impl_->context.read_rgb(out, &impl_->timer);
  impl_->text.blend(impl_->settings.caption, impl_->overlay_lines, out);
  impl_->timer.lap("text (CPU)");
  if (impl_->settings.fxaa) {
    fxaa_rgb(out, impl_->context.width(), impl_->context.height(), impl_->fxaa_scratch);
    impl_->timer.lap("FXAA (CPU)");
  }
}

void Renderer::set_pass_timing(bool on) { impl_->timer.enable(on); }
std::vector<RenderPassTime> Renderer::pass_times() const { return impl_->timer.times(); }

int Renderer::width() const { return impl_->context.width(); }
int Renderer::height() const { return impl_->context.height(); }
int Renderer::samples() const { return impl_->context.samples(); }
std::string Renderer::gl_version() const {
  impl_->context.make_current();
  return impl_->context.gl_version();
}

}  // namespace tissu
