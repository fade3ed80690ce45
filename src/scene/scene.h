// A scene file, validated: every value checked, every unit SI. docs/scenes.md documents
// each key. Building turns it into the Model and the initial State.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "mesh/generate.h"
#include "physics/model.h"
#include "scene/json_reader.h"

namespace tissu {

struct MeshSpec {
  enum class Kind { Rectangle, Disk, Sliver, File };
  Kind kind = Kind::Rectangle;
  Vec2 size = Vec2(1.0, 1.0);  // rectangle width, height, m
  double radius = 0.5;         // disk radius, m
  int triangles = 1000;        // requested triangle count (about)
  bool irregular = true;
  uint64_t seed = 1;
  std::optional<double> inner_radius;  // disk: a circle of vertices at this radius, m
  std::optional<DiskGrading> grading;  // disk: a band meshed finer (needs inner_radius)
  std::string file;            // resolved path (relative paths are relative to the scene file)
  double uv_scale = 1.0;       // texture coordinates -> metres
};

struct ClothTransform {
  Vec3 scale = Vec3::Ones();       // applied to positions only: != 1 pre-stretches the cloth
  Vec3 rotate_axis = Vec3::UnitZ();
  double rotate_degrees = 0.0;
  Vec3 translate = Vec3::Zero();   // m
};

// A crumpled random start: a smooth random displacement field of the given amplitude
// (sum of random plane waves in (u, v) with wavelengths 0.1-0.5 m) added to the positions.
struct CrumpleSpec {
  double amplitude = 0.0;  // m
  uint64_t seed = 1;
};

// The surface file of a mesh obstacle and how it is placed (read when the simulation is
// built): positions are scaled, rotated, then translated, as the cloth's transform does.
struct ObstacleMeshSpec {
  size_t obstacle = 0;       // index in Scene::obstacles
  std::string path;          // JSON path of the "mesh" object (for messages)
  std::string file;          // resolved path
  ClothTransform transform;
};

struct PinSpec {
  std::string path;                     // JSON path, for errors
  std::vector<long long> vertices;
  std::optional<std::pair<Vec3, Vec3>> box;  // world min, max at t = 0, m
  struct Ball {
    Vec3 center;    // world, at t = 0, m
    double radius;  // m
  };
  std::optional<Ball> disk;  // the vertices within `radius` of `center` (in 3D)
};

struct Scene {
  std::string file;  // scene file path ("" when built in memory)
  std::vector<std::string> overrides;  // the --set assignments applied, for naming errors
  std::string name;
  double dt = 0.0;        // s
  long long steps = 0;
  Integrator integrator = Integrator::SymplecticEuler;
  ImplicitOptions implicit;
  double max_speed = 100.0;  // m/s

  MeshSpec mesh;
  ClothTransform transform;
  Vec3 initial_velocity = Vec3::Zero();  // m/s
  std::optional<CrumpleSpec> crumple;
  Material material;
  std::vector<PinSpec> pins;

  std::optional<Vec3> gravity;
  std::optional<double> air_damping;
  std::optional<Wind> wind;
  std::optional<PositionCorrection> position_correction;
  std::vector<Obstacle> obstacles;
  std::vector<ObstacleMeshSpec> obstacle_meshes;
  std::optional<SelfCollision> self_collision;

  Json render;  // the raw `render` block (null when absent), validated by the renderer
  // The document after overrides, presets expanded and paths absolute (set by load_scene;
  // null otherwise): scene/resolved_scene.h.
  Json resolved;
};

// Reads a scene file (JSON with // comments). Syntax errors name line and column.
Json read_scene_json(const std::string& file);

// Applies one `--set key.path=value` override (value parsed as JSON if it parses, else a
// string). Array elements are addressed by index: obstacles.0.sphere.radius.
void apply_override(Json& doc, const std::string& assignment);

// Where a file named in a scene is: a relative path is looked up next to the scene file,
// then in Tissu's data directory (data/ beside the tissu program, where the build puts the
// sample meshes of Debian's libcgal-demo, and the build tree's data/). Returns the first
// that exists, else the path next to the scene file.
std::string resolve_scene_file(const std::string& name, const std::string& scene_file);

// Validates a scene document. `file` is used to resolve mesh paths. Errors are InputError
// "<json.path>: <problem>".
Scene parse_scene(const Json& doc, const std::string& file);

// read + overrides + parse; errors prefixed with the file name, or with the override that
// caused them.
Scene load_scene(const std::string& file, const std::vector<std::string>& overrides = {});

// The error for `message` ("<json.path>: <problem>") about a value of `scene`, named as
// load_scene names its own: by the --set override that set the value, else by the scene
// file. For the parts of a scene validated later (its render block).
InputError scene_error(const Scene& scene, const std::string& message);

// Model and initial State of a scene (loads or generates the mesh, applies the transform,
// pins, masses).
struct Simulation {
  Model model;
  State state;
};
Simulation build_simulation(const Scene& scene);

}  // namespace tissu
