// Scene -> Model + initial State.
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include <iostream>
#include <sstream>

#include "collision/closed_surface.h"
#include "mesh/generate.h"
#include "mesh/load.h"
#include "mesh/random.h"
#include "physics/bending.h"
#include "scene/json_reader.h"
#include "scene/scene.h"

namespace tissu {

namespace {

TriMesh generate_or_load(const MeshSpec& spec) {
  switch (spec.kind) {
    case MeshSpec::Kind::Rectangle:
      return generate_rectangle(spec.size.x(), spec.size.y(), spec.triangles, spec.irregular,
                                spec.seed);
    case MeshSpec::Kind::Disk:
      if (spec.grading) {
        return generate_disk(spec.radius, spec.triangles, spec.seed, *spec.inner_radius,
                             *spec.grading);
      }
      if (spec.inner_radius) {
        return generate_disk(spec.radius, spec.triangles, spec.irregular, spec.seed,
                             *spec.inner_radius);
      }
      return generate_disk(spec.radius, spec.triangles, spec.irregular, spec.seed);
    case MeshSpec::Kind::Sliver:
      return generate_sliver_rectangle(spec.size.x(), spec.size.y(), spec.triangles);
    case MeshSpec::Kind::File:
      return load_mesh(spec.file, spec.uv_scale);
  }
  return {};
}

// Mesh errors name the scene key they come from.
TriMesh make_mesh(const MeshSpec& spec) {
  try {
    return generate_or_load(spec);
  } catch (const InputError& e) {
    throw InputError(std::string(spec.kind == MeshSpec::Kind::File ? "cloth.mesh.file: "
                                                                   : "cloth.mesh: ") +
                     e.what());
  }
}

void apply_transform(const ClothTransform& t, Vec3List& positions) {
  const Eigen::AngleAxisd rotation(t.rotate_degrees * M_PI / 180.0, t.rotate_axis);
  const Mat3 linear = rotation.toRotationMatrix() * t.scale.asDiagonal();
  for (Vec3& p : positions) p = linear * p + t.translate;
}

// Huge scales, translations or crumple amplitudes can overflow a position.
void require_finite(const Vec3List& x, const std::string& key) {
  for (size_t i = 0; i < x.size(); ++i) {
    if (!x[i].allFinite()) {
      throw InputError(key + ": moves vertex " + std::to_string(i) +
                       " to a non-finite position");
    }
  }
}

// Pins by vertex id need ids that are the file's: refused for a file whose corners were
// welded by position (STL stores no vertex list).
void require_file_vertex_ids(const std::vector<PinSpec>& pins, const TriMesh& mesh,
                             const MeshSpec& spec) {
  if (mesh.file_vertex_ids) return;
  for (const PinSpec& pin : pins) {
    if (pin.vertices.empty()) continue;
    throw InputError(pin.path + ".vertices: " + spec.file + " has no vertex list of its own "
                     "(corners at the same position were welded, as for STL), so vertex ids "
                     "are not the file's: pin by \"box\" instead, or use OBJ, PLY or OFF");
  }
}

// Pins every vertex whose position x satisfies inside(x); a region (at `path`) that
// selects none is an error.
template <typename Inside>
void pin_region(const Vec3List& x, const std::string& path, std::vector<uint8_t>& pinned,
                Inside inside) {
  int selected = 0;
  for (size_t i = 0; i < x.size(); ++i) {
    if (!inside(x[i])) continue;
    pinned[i] = 1;
    ++selected;
  }
  if (selected == 0) throw InputError(path + ": selects no vertex");
}

void apply_pins(const std::vector<PinSpec>& pins, const Vec3List& x, std::vector<uint8_t>& pinned) {
  const long long n = static_cast<long long>(x.size());
  for (const PinSpec& pin : pins) {
    for (size_t k = 0; k < pin.vertices.size(); ++k) {
      const long long id = pin.vertices[k];
      if (id >= n) {
        throw InputError(element_path(pin.path + ".vertices", k) + ": vertex " +
                         std::to_string(id) + " out of range (mesh has " + std::to_string(n) +
                         " vertices)");
      }
      pinned[id] = 1;
    }
    if (pin.box) {
      const auto& [lo, hi] = *pin.box;
      pin_region(x, pin.path + ".box", pinned, [&](const Vec3& p) {
        return (p.array() >= lo.array()).all() && (p.array() <= hi.array()).all();
      });
    }
    if (pin.disk) {
      // A relative 1e-9 keeps the vertices placed on a circle of that radius (a disk
      // mesh's inner_radius) despite rounding.
      const double reach = pin.disk->radius * (1.0 + 1e-9);
      pin_region(x, pin.path + ".disk", pinned,
                 [&](const Vec3& p) { return (p - pin.disk->center).norm() <= reach; });
    }
  }
}

// Smooth random displacement: 8 plane waves in (u, v) with random directions, wavelengths
// in [0.1, 0.5] m, phases and displacement directions; scaled so the largest possible
// displacement is `amplitude`.
void apply_crumple(const CrumpleSpec& spec, const Vec2List& uv, Vec3List& x) {
  constexpr int kWaves = 8;
  PortableRandom random(spec.seed);
  struct Wave {
    Vec2 k;
    double phase;
    Vec3 direction;
  };
  std::vector<Wave> waves;
  for (int i = 0; i < kWaves; ++i) {
    const double angle = random.uniform(0.0, 2.0 * M_PI);
    const double wavelength = random.uniform(0.1, 0.5);
    const double phase = random.uniform(0.0, 2.0 * M_PI);
    Vec3 d(random.uniform(-1, 1), random.uniform(-1, 1), random.uniform(-1, 1));
    waves.push_back({Vec2(std::cos(angle), std::sin(angle)) * (2.0 * M_PI / wavelength), phase,
                     d.normalized()});
  }
  for (size_t i = 0; i < x.size(); ++i) {
    Vec3 offset = Vec3::Zero();
    for (const Wave& w : waves) offset += std::sin(w.k.dot(uv[i]) + w.phase) * w.direction;
    x[i] += (spec.amplitude / kWaves) * offset;
  }
}

// Reads, places and checks the surface of a mesh obstacle. Errors name the scene key.
void load_obstacle_surface(const ObstacleMeshSpec& spec, Obstacle& ob) {
  const std::string key = spec.path + ".file";
  SurfaceFile file;
  try {
    file = load_surface(spec.file);
  } catch (const InputError& e) {
    throw InputError(key + ": " + e.what());
  }
  apply_transform(spec.transform, file.positions);
  require_finite(file.positions, spec.path + ".transform");
  try {
    auto surface = std::make_shared<ClosedSurface>(std::move(file.positions),
                                                   std::move(file.triangles), spec.file, file.places);
    if (surface->reversed()) {
      std::cerr << "warning: " << spec.file << ": the triangles faced inward; reversed\n";
    }
    const CrossingReport& crossings = surface->self_crossings();
    if (crossings.any()) {
      std::cerr << "warning: " << spec.file << ": the surface crosses itself at " << crossings.count
                << " pairs of triangles (first: " << file.places[crossings.pairs[0].first] << " and "
                << file.places[crossings.pairs[0].second]
                << "); inside it, near those places, points may be taken for outside\n";
    }
    ob.center = surface->bounds().center();
    ob.surface = std::move(surface);
  } catch (const InputError& e) {
    throw InputError(key + ": " + e.what());
  }
}

// How far inside an obstacle's surface a cloth vertex may start, m: rounding of a cloth
// laid on a surface, not an overlap.
constexpr double kStartInsideTolerance = 1e-6;

// The cloth's free vertices start outside every obstacle. One that starts inside is pushed
// out in the first step at any speed that takes (a sheet started through a sphere reached
// 1e4 m/s), which a run then reports as a divergence with a hint to shrink the step. A
// pinned vertex is never pushed, and may be held inside.
void require_cloth_outside_obstacles(const Model& model, const Vec3List& x) {
  for (size_t o = 0; o < model.obstacles.size(); ++o) {
    const Obstacle& ob = model.obstacles[o];
    Vec3 normal;
    double deepest = kStartInsideTolerance;  // m
    size_t vertex = x.size();
    for (size_t i = 0; i < x.size(); ++i) {
      if (model.pinned[i]) continue;
      const double depth = -ob.signed_distance(x[i], 0.0, &normal);  // m
      if (depth <= deepest) continue;
      deepest = depth;
      vertex = i;
    }
    if (vertex == x.size()) continue;
    std::ostringstream what;
    what << element_path("obstacles", o) << '.' << obstacle_kind_name(ob.kind) << ": cloth vertex "
         << vertex << " starts " << deepest
         << " m inside it (the cloth must start outside every obstacle)";
    throw InputError(what.str());
  }
}

Simulation build(const Scene& scene) {
  TriMesh mesh = make_mesh(scene.mesh);
  require_file_vertex_ids(scene.pins, mesh, scene.mesh);
  Simulation sim;
  Model& model = sim.model;
  model.triangles = std::move(mesh.triangles);
  model.rest_uv = std::move(mesh.rest_uv);
  model.material = scene.material;
  model.integrator = scene.integrator;
  model.dt = scene.dt;
  model.max_speed = scene.max_speed;
  model.implicit = scene.implicit;
  model.gravity = scene.gravity;
  model.air_damping = scene.air_damping;
  model.wind = scene.wind;
  model.position_correction = scene.position_correction;
  model.obstacles = scene.obstacles;
  for (const ObstacleMeshSpec& spec : scene.obstacle_meshes) {
    Obstacle& ob = model.obstacles[spec.obstacle];
    load_obstacle_surface(spec, ob);
    ob.thickness = std::max(ob.thickness, kMeshThicknessFloor);
  }
  model.self_collision = scene.self_collision;

  State& state = sim.state;
  state.x = std::move(mesh.positions);
  if (scene.crumple) apply_crumple(*scene.crumple, model.rest_uv, state.x);
  require_finite(state.x, "cloth.crumple.amplitude");
  apply_transform(scene.transform, state.x);
  require_finite(state.x, "cloth.transform");
  model.pinned.assign(state.x.size(), 0);
  apply_pins(scene.pins, state.x, model.pinned);
  require_cloth_outside_obstacles(model, state.x);
  precompute_rest(model);
  if (model.material.bending > 0.0) {
    model.bending = std::make_shared<const BendingModel>(build_bending(
        model.triangles, model.rest_uv, model.material.bending, model.material.bending_warp,
        model.pinned));
  }
  state.v.assign(state.x.size(), scene.initial_velocity);
  for (size_t i = 0; i < state.v.size(); ++i) {
    if (model.pinned[i]) state.v[i].setZero();
  }
  return sim;
}

}  // namespace

Simulation build_simulation(const Scene& scene) {
  try {
    return build(scene);
  } catch (const InputError& e) {
    if (scene.file.empty()) throw;
    throw InputError(scene.file + ": " + e.what());  // one line naming the scene file
  }
}

}  // namespace tissu
