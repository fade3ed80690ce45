// Strict parsing of a scene document into a Scene (docs/scenes.md).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>

#include "core/executable_dir.h"
#include "physics/materials.h"
#include "scene/scene.h"

#ifndef TISSU_DATA_DIR
#define TISSU_DATA_DIR ""
#endif

namespace tissu {

namespace {

Integrator parse_integrator(JsonReader& root) {
  const std::string name =
      root.choice("integrator", {"explicit_euler", "symplectic_euler", "benameur_djedi",
                                 "backward_euler", "bdf2", "implicit_midpoint"});
  if (name == "explicit_euler") return Integrator::ExplicitEuler;
  if (name == "symplectic_euler") return Integrator::SymplecticEuler;
  if (name == "benameur_djedi") return Integrator::BenameurDjedi;
  if (name == "backward_euler") return Integrator::BackwardEuler;
  if (name == "implicit_midpoint") return Integrator::ImplicitMidpoint;
  return Integrator::Bdf2;
}

// A disk's circle of vertices at `inner_radius` and its band meshed finer (generate.h,
// DiskGrading), both optional; the grading needs the circle. Lengths in m.
void parse_disk_circles(JsonReader& mesh, MeshSpec& spec) {
  const double r = spec.radius;
  if (mesh.has("inner_radius")) {
    spec.inner_radius = mesh.number("inner_radius", Range{0.0, r, true, true});
  }
  if (!mesh.has("grading")) return;
  JsonReader g = mesh.object("grading");
  if (!spec.inner_radius) {
    throw InputError(g.path() + ": needs " + mesh.path_of("inner_radius") +
                     " (the graded disk has a circle of vertices there)");
  }
  DiskGrading grading;
  grading.inner = g.number("inner", Range{0.0, r, false, true});
  grading.outer = g.number("outer", Range{grading.inner, r, true, false});
  grading.fine_ratio = g.number("fine_ratio", Range{0.0, 1.0, true, false});
  grading.transition = g.number("transition", 0.0, Range::between(0.0, r));
  g.finish();
  spec.grading = grading;
}

MeshSpec parse_mesh(JsonReader mesh, const std::string& scene_file) {
  MeshSpec spec;
  if (mesh.has("file")) {
    spec.kind = MeshSpec::Kind::File;
    const std::string file = mesh.string("file");
    if (file.empty()) throw InputError(mesh.path_of("file") + ": must not be empty");
    std::filesystem::path p(file);
    if (p.is_relative() && !scene_file.empty()) {
      p = std::filesystem::path(scene_file).parent_path() / p;
    }
    spec.file = p.lexically_normal().string();
    spec.uv_scale = mesh.number("uv_scale", 1.0, Range::positive());
    mesh.finish();
    return spec;
  }
  const std::string kind = mesh.choice("generate", {"rectangle", "disk", "sliver_rectangle"});
  // Lengths from 1 um to 1000 km: beyond, areas and spacings underflow or overflow and the
  // generators place coincident points or loop over absurd point counts.
  const Range length = Range::between(1e-6, 1e6);
  if (kind == "disk") {
    spec.kind = MeshSpec::Kind::Disk;
    spec.radius = mesh.number("radius", length);
    parse_disk_circles(mesh, spec);
  } else {
    spec.kind = kind == "rectangle" ? MeshSpec::Kind::Rectangle : MeshSpec::Kind::Sliver;
    spec.size = mesh.vec2("size", length);
  }
  // 4 million triangles is about 1 GiB of simulation state: beyond that, refuse.
  spec.triangles = static_cast<int>(mesh.integer("triangles", Range::between(2, 4e6)));
  // A long thin rectangle needs about one triangle per unit of aspect ratio along its
  // boundary alone: more than requested would be generated (the generators' work grows
  // with the aspect ratio, not with the requested count).
  const double aspect = spec.size.maxCoeff() / spec.size.minCoeff();
  if (spec.kind != MeshSpec::Kind::Disk && aspect > spec.triangles) {
    throw InputError(mesh.path_of("size") + ": aspect ratio " + format_number(aspect) +
                     " needs " + mesh.path_of("triangles") + " >= " + format_number(aspect) +
                     ", got " + std::to_string(spec.triangles));
  }
  // A graded disk's rings are always irregular: the key does not apply to it.
  if (!spec.grading) spec.irregular = mesh.boolean("irregular", true);
  spec.seed = static_cast<uint64_t>(mesh.integer("seed", 1, Range::between(0, 9e15)));
  mesh.finish();
  return spec;
}

ClothTransform parse_transform(JsonReader t) {
  ClothTransform out;
  if (t.has("scale")) {
    const Json& s = t.raw("scale");
    out.scale = s.is_array() ? checked_vec3(s, t.path_of("scale"))
                             : Vec3::Constant(checked_number(s, t.path_of("scale"),
                                                             Range::positive()));
    for (int i = 0; i < 3; ++i) {
      if (!(out.scale[i] > 0.0)) {
        throw InputError(element_path(t.path_of("scale"), i) + ": must be > 0, got " +
                         format_number(out.scale[i]));
      }
    }
  }
  if (t.has("rotate")) {
    JsonReader r = t.object("rotate");
    out.rotate_axis = r.vec3("axis");
    if (out.rotate_axis.norm() == 0.0) throw InputError(r.path_of("axis") + ": must not be zero");
    out.rotate_axis.normalize();
    out.rotate_degrees = r.number("degrees");
    r.finish();
  }
  out.translate = t.vec3("translate", Vec3::Zero());
  t.finish();
  return out;
}

// The preset named `name`, or an error at `path` listing the presets.
Material preset_at(const std::string& name, const std::string& path) {
  if (auto preset = material_preset(name)) return *preset;
  std::string list;
  for (const std::string& n : material_preset_names()) list += (list.empty() ? "" : ", ") + n;
  const std::string near = closest_key(name, material_preset_names());
  throw InputError(path + ": unknown preset \"" + name + "\"" +
                   (near.empty() ? "" : " (did you mean \"" + near + "\"?)") +
                   "; expected one of " + list + ", or an object");
}

// A preset name, or an object: with "preset", that preset with the named fields replaced;
// without, every required field given.
Material parse_material(JsonReader& cloth) {
  const Json& value = cloth.raw("material");
  const std::string path = cloth.path_of("material");
  if (value.is_string()) return preset_at(value.get<std::string>(), path);
  JsonReader m(value, path);
  std::optional<Material> base;
  if (m.has("preset")) {
    base = preset_at(m.string("preset"), m.path_of("preset"));
    base->name += ", modified";
  }
  Material mat = base.value_or(Material{});
  if (!base) mat.name = "custom";
  // A field of the preset when there is one, else required.
  auto field = [&](JsonReader& r, const std::string& key, double preset_value, Range range) {
    return base ? r.number(key, preset_value, range) : r.number(key, range);
  };
  mat.density = field(m, "density", mat.density, Range::positive());
  if (base && !m.has("stiffness")) {
    m.accept("stiffness");
  } else {
    JsonReader k = m.object("stiffness");
    mat.weft = field(k, "weft", mat.weft, Range::positive());
    mat.warp = field(k, "warp", mat.warp, Range::positive());
    mat.coupling = k.number("coupling", base ? mat.coupling : 0.0, Range::any());
    mat.shear = field(k, "shear", mat.shear, Range::positive());
    k.finish();
  }
  // E must be positive definite (weft, warp > 0 and coupling^2 < weft * warp).
  if (!(mat.coupling * mat.coupling < mat.weft * mat.warp)) {
    throw InputError(path + ".stiffness.coupling: must satisfy coupling^2 < weft * warp (E "
                     "positive definite), got " + format_number(mat.coupling));
  }
  mat.bending = m.number("bending", base ? mat.bending : 0.0, Range::non_negative());
  mat.bending_warp =
      m.number("bending_warp", base ? mat.bending_warp : -1.0, Range::non_negative());
  mat.damping = m.number("damping", base ? mat.damping : 0.0, Range::non_negative());
  mat.compression_ratio =
      m.number("compression_ratio", mat.compression_ratio, Range{0.0, 1.0, true, false});
  m.finish();
  return mat;
}

std::vector<PinSpec> parse_pins(JsonReader& cloth) {
  std::vector<PinSpec> pins;
  if (!cloth.has("pins")) return pins;
  const Json& list = cloth.raw("pins");
  const std::string path = cloth.path_of("pins");
  if (!list.is_array()) throw InputError(path + ": must be an array of pin selections");
  for (size_t i = 0; i < list.size(); ++i) {
    JsonReader p(list[i], element_path(path, i));
    PinSpec pin;
    pin.path = p.path();
    if (p.has("vertices")) {
      const Json& ids = p.raw("vertices");
      if (!ids.is_array() || ids.empty()) {
        throw InputError(p.path_of("vertices") + ": must be a non-empty array of vertex ids");
      }
      for (size_t k = 0; k < ids.size(); ++k) {
        const std::string at = element_path(p.path_of("vertices"), k);
        const double id = checked_number(ids[k], at, Range::non_negative());
        if (id != std::floor(id)) throw InputError(at + ": must be an integer vertex id");
        pin.vertices.push_back(static_cast<long long>(id));
      }
    } else if (p.has("box")) {
      JsonReader b = p.object("box");
      const Vec3 lo = b.vec3("min"), hi = b.vec3("max");
      b.finish();
      for (int a = 0; a < 3; ++a) {
        if (lo[a] > hi[a]) throw InputError(b.path() + ": min must not exceed max on each axis");
      }
      pin.box = std::make_pair(lo, hi);
    } else if (p.has("disk")) {
      JsonReader d = p.object("disk");
      pin.disk = PinSpec::Ball{d.vec3("center"), d.number("radius", Range::positive())};
      d.finish();
    } else {
      throw InputError(p.path() + ": needs \"vertices\", \"box\" or \"disk\"");
    }
    p.finish();
    pins.push_back(pin);
  }
  return pins;
}

Wind parse_wind(JsonReader w) {
  Wind wind;
  wind.velocity = w.vec3("velocity");
  wind.drag = w.number("drag", Range::positive());
  if (w.has("gust")) {
    JsonReader g = w.object("gust");
    wind.gust_amplitude = g.number("amplitude", Range::between(0.0, 10.0));
    wind.gust_period = g.number("period", Range::positive());
    g.finish();
  }
  w.finish();
  return wind;
}

Eigen::Quaterniond parse_rotation(JsonReader r) {
  const Vec3 axis = r.vec3("axis");
  if (axis.norm() == 0.0) throw InputError(r.path_of("axis") + ": must not be zero");
  const double degrees = r.number("degrees");
  r.finish();
  return Eigen::Quaterniond(Eigen::AngleAxisd(degrees * M_PI / 180.0, axis.normalized()));
}

// Keyframes: ascending times; rotations only for obstacles that can turn (meshes).
std::vector<Keyframe> parse_keyframes(JsonReader& m, bool can_turn) {
  std::vector<Keyframe> keys;
  const Json& list = m.raw("keyframes");
  const std::string path = m.path_of("keyframes");
  if (!list.is_array() || list.empty()) {
    throw InputError(path + ": must be a non-empty array of {\"time\", \"translate\", \"rotate\"}");
  }
  for (size_t i = 0; i < list.size(); ++i) {
    JsonReader k(list[i], element_path(path, i));
    Keyframe key;
    key.time = k.number("time", Range::non_negative());
    if (!keys.empty() && !(key.time > keys.back().time)) {
      throw InputError(k.path_of("time") + ": keyframe times must increase, got " +
                       format_number(key.time) + " after " + format_number(keys.back().time));
    }
    key.translation = k.vec3("translate", Vec3::Zero());
    if (k.has("rotate")) {
      if (!can_turn) {
        throw InputError(k.path_of("rotate") +
                         ": only mesh obstacles turn; spheres, cylinders and planes translate");
      }
      key.rotation = parse_rotation(k.object("rotate"));
    }
    k.finish();
    keys.push_back(key);
  }
  return keys;
}

ObstacleMotion parse_motion(JsonReader m, bool can_turn) {
  ObstacleMotion motion;
  motion.velocity = m.vec3("velocity", Vec3::Zero());
  if (m.has("amplitude") || m.has("period")) {
    motion.amplitude = m.vec3("amplitude");
    motion.period = m.number("period", Range::positive());
  }
  if (m.has("keyframes")) motion.keyframes = parse_keyframes(m, can_turn);
  m.finish();
  return motion;
}

Vec3 unit_vector(JsonReader& r, const std::string& key) {
  const Vec3 v = r.vec3(key);
  if (!(v.norm() > 0.0)) throw InputError(r.path_of(key) + ": must not be the zero vector");
  return v.normalized();
}

// One element of "obstacles"; a mesh obstacle also adds its surface file to the scene.
Obstacle parse_obstacle(const Json& value, const std::string& path, Scene& scene) {
  JsonReader wrapper(value, path);
  const std::vector<std::string> kinds = {"sphere", "cylinder", "plane", "mesh"};
  if (!value.is_object() || value.size() != 1) {
    // Name what is wrong: a second obstacle, or a key (friction, thickness) written beside
    // the obstacle instead of inside it.
    std::vector<std::string> held, other;
    if (value.is_object()) {
      for (auto it = value.begin(); it != value.end(); ++it) {
        (std::find(kinds.begin(), kinds.end(), it.key()) != kinds.end() ? held : other)
            .push_back(it.key());
      }
    }
    if (held.size() == 1 && !other.empty()) {
      throw InputError(wrapper.path_of(other.front()) + ": belongs inside \"" + held.front() +
                       "\", as {\"" + held.front() + "\": {..., \"" + other.front() + "\": ...}}");
    }
    if (held.size() > 1) {
      throw InputError(path + ": holds both \"" + held[0] + "\" and \"" + held[1] +
                       "\"; each element of \"obstacles\" is one obstacle");
    }
    throw InputError(path + ": must hold exactly one of \"sphere\", \"cylinder\", \"plane\", "
                     "\"mesh\"");
  }
  const std::string kind = value.begin().key();
  Obstacle ob;
  if (std::find(kinds.begin(), kinds.end(), kind) == kinds.end()) {
    const std::string near = closest_key(kind, kinds);
    throw InputError(wrapper.path_of(kind) + ": unknown obstacle" +
                     (near.empty() ? "" : " (did you mean \"" + near + "\"?)") +
                     "; expected sphere, cylinder, plane or mesh");
  }
  JsonReader r = wrapper.object(kind);
  if (kind == "sphere") {
    ob.kind = ObstacleKind::Sphere;
    ob.center = r.vec3("center");
    ob.radius = r.number("radius", Range::positive());
  } else if (kind == "cylinder") {
    ob.kind = ObstacleKind::Cylinder;
    ob.center = r.vec3("center");
    ob.axis = unit_vector(r, "axis");
    ob.radius = r.number("radius", Range::positive());
    ob.half_length = r.number("length", Range::positive()) / 2.0;
  } else if (kind == "plane") {
    ob.kind = ObstacleKind::Plane;
    ob.center = r.vec3("point");
    ob.axis = unit_vector(r, "normal");
  } else {
    ob.kind = ObstacleKind::Mesh;
    ObstacleMeshSpec spec;
    spec.obstacle = scene.obstacles.size();
    spec.path = r.path();
    const std::string file = r.string("file");
    if (file.empty()) throw InputError(r.path_of("file") + ": must not be empty");
    spec.file = resolve_scene_file(file, scene.file);
    if (r.has("transform")) spec.transform = parse_transform(r.object("transform"));
    scene.obstacle_meshes.push_back(spec);
  }
  ob.friction = r.number("friction", 0.0, Range::non_negative());
  ob.thickness = r.number("thickness", 0.0, Range::between(0.0, 1.0));
  if (r.has("motion")) ob.motion = parse_motion(r.object("motion"), kind == "mesh");
  r.finish();
  wrapper.finish();
  return ob;
}

}  // namespace

std::string resolve_scene_file(const std::string& name, const std::string& scene_file) {
  namespace fs = std::filesystem;
  fs::path beside(name);
  if (beside.is_relative() && !scene_file.empty()) beside = fs::path(scene_file).parent_path() / beside;
  beside = beside.lexically_normal();
  if (fs::path(name).is_absolute() || fs::exists(beside)) return beside.string();
  for (const std::string& dir : {executable_dir() + "/data", std::string(TISSU_DATA_DIR)}) {
    if (dir.empty() || dir == "/data") continue;
    const fs::path candidate = (fs::path(dir) / name).lexically_normal();
    if (fs::exists(candidate)) return candidate.string();
  }
  return beside.string();
}

Scene parse_scene(const Json& doc, const std::string& file) {
  JsonReader root(doc, "");
  Scene scene;
  scene.file = file;
  scene.name = root.string("name");
  scene.dt = root.number("dt", Range{0.0, 1.0, true, false});
  if (root.has("steps") == root.has("duration")) {
    throw InputError("steps: give exactly one of \"steps\" or \"duration\"");
  }
  if (root.has("steps")) {
    scene.steps = root.integer("steps", Range::between(0, 1e9));
    root.accept("duration");
  } else {
    const double duration = root.number("duration", Range::non_negative());
    const double steps = std::round(duration / scene.dt);
    if (steps > 1e9) throw InputError("duration: needs more than 1e9 steps at this dt");
    scene.steps = static_cast<long long>(steps);
    root.accept("steps");
  }
  scene.integrator = parse_integrator(root);
  if (root.has("implicit")) {
    JsonReader im = root.object("implicit");
    const ImplicitOptions defaults;
    scene.implicit.max_newton_iterations = static_cast<int>(
        im.integer("newton_iterations", defaults.max_newton_iterations, Range::between(1, 100)));
    scene.implicit.newton_tolerance =
        im.number("newton_tolerance", defaults.newton_tolerance, Range::positive());
    scene.implicit.newton_motion_tolerance = im.number(
        "newton_motion_tolerance", defaults.newton_motion_tolerance, Range::non_negative());
    scene.implicit.cg_tolerance = im.number("cg_tolerance", defaults.cg_tolerance, Range::positive());
    std::vector<std::string> solvers;
    for (LinearSolver s : kLinearSolvers) solvers.emplace_back(linear_solver_name(s));
    const std::string solver = im.choice(
        "linear_solver", solvers, linear_solver_name(defaults.linear_solver));
    for (LinearSolver s : kLinearSolvers) {
      if (solver == linear_solver_name(s)) scene.implicit.linear_solver = s;
    }
    const std::string search = im.choice("line_search", {"potential", "residual"}, "potential");
    scene.implicit.line_search =
        search == "potential" ? LineSearch::Potential : LineSearch::Residual;
    const std::string contact = im.choice("contact", {"constraints", "barrier"}, "constraints");
    scene.implicit.contact =
        contact == "constraints" ? ContactModel::Constraints : ContactModel::Barrier;
    if (im.has("barrier_distance")) {
      scene.implicit.barrier_distance = im.number("barrier_distance", Range::positive());
    }
    if (im.has("barrier_stiffness_dt")) {
      scene.implicit.barrier_stiffness_dt = im.number("barrier_stiffness_dt", Range::positive());
    }
    scene.implicit.barrier_damping =
        im.number("barrier_damping", defaults.barrier_damping, Range::non_negative());
    im.finish();
  }
  scene.max_speed = root.number("max_speed", 100.0, Range::positive());

  JsonReader cloth = root.object("cloth");
  scene.mesh = parse_mesh(cloth.object("mesh"), file);
  if (cloth.has("transform")) scene.transform = parse_transform(cloth.object("transform"));
  scene.initial_velocity = cloth.vec3("velocity", Vec3::Zero());
  if (cloth.has("crumple")) {
    JsonReader c = cloth.object("crumple");
    scene.crumple = CrumpleSpec{c.number("amplitude", Range::positive()),
                                static_cast<uint64_t>(c.integer("seed", 1, Range::between(0, 9e15)))};
    c.finish();
  }
  cloth.accept("crumple");
  scene.material = parse_material(cloth);
  scene.pins = parse_pins(cloth);
  cloth.finish();

  if (root.has("gravity")) scene.gravity = root.vec3("gravity");
  if (root.has("air_damping")) scene.air_damping = root.number("air_damping", Range::positive());
  if (root.has("wind")) scene.wind = parse_wind(root.object("wind"));
  if (root.has("position_correction")) {
    JsonReader pc = root.object("position_correction");
    PositionCorrection c;
    c.threshold = pc.number("threshold", Range::positive());
    c.iterations = static_cast<int>(pc.integer("iterations", 1, Range::between(1, 1000)));
    pc.finish();
    scene.position_correction = c;
  }
  if (root.has("obstacles")) {
    const Json& list = root.raw("obstacles");
    if (!list.is_array()) throw InputError("obstacles: must be an array");
    for (size_t i = 0; i < list.size(); ++i) {
      scene.obstacles.push_back(parse_obstacle(list[i], element_path("obstacles", i), scene));
    }
  }
  if (root.has("self_collision")) {
    JsonReader sc = root.object("self_collision");
    SelfCollision self;
    self.thickness = sc.number("thickness", Range{0.0, 1.0, true, false});
    self.friction = sc.number("friction", 0.0, Range::non_negative());
    sc.finish();
    scene.self_collision = self;
  }
  if (root.has("render")) scene.render = root.raw("render");
  root.accept("render");
  root.accept("gravity");
  root.accept("air_damping");
  root.accept("wind");
  root.accept("position_correction");
  root.accept("obstacles");
  root.accept("self_collision");
  root.accept("implicit");
  root.finish();
  return scene;
}

}  // namespace tissu
