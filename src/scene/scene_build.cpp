// Scene -> Model + initial State.
#include <Eigen/Geometry>
#include <cmath>

#include "mesh/generate.h"
#include "mesh/load.h"
#include "physics/bending.h"
#include "scene/scene.h"

namespace tissu {

namespace {

TriMesh make_mesh(const MeshSpec& spec) {
  switch (spec.kind) {
    case MeshSpec::Kind::Rectangle:
      return generate_rectangle(spec.size.x(), spec.size.y(), spec.triangles, spec.irregular,
                                spec.seed);
    case MeshSpec::Kind::Disk:
      return generate_disk(spec.radius, spec.triangles, spec.irregular, spec.seed);
    case MeshSpec::Kind::Sliver:
      return generate_sliver_rectangle(spec.size.x(), spec.size.y(), spec.triangles);
    case MeshSpec::Kind::File:
      return load_mesh(spec.file, spec.uv_scale);
  }
  return {};
}

void apply_transform(const ClothTransform& t, Vec3List& positions) {
  const Eigen::AngleAxisd rotation(t.rotate_degrees * M_PI / 180.0, t.rotate_axis);
  const Mat3 linear = rotation.toRotationMatrix() * t.scale.asDiagonal();
  for (Vec3& p : positions) p = linear * p + t.translate;
}

void apply_pins(const std::vector<PinSpec>& pins, const Vec3List& x, std::vector<uint8_t>& pinned) {
  const long long n = static_cast<long long>(x.size());
  for (const PinSpec& pin : pins) {
    int selected = 0;
    for (size_t k = 0; k < pin.vertices.size(); ++k) {
      const long long id = pin.vertices[k];
      if (id >= n) {
        throw InputError(element_path(pin.path + ".vertices", k) + ": vertex " +
                         std::to_string(id) + " out of range (mesh has " + std::to_string(n) +
                         " vertices)");
      }
      pinned[id] = 1;
      ++selected;
    }
    if (pin.box) {
      const auto& [lo, hi] = *pin.box;
      for (long long i = 0; i < n; ++i) {
        if ((x[i].array() >= lo.array()).all() && (x[i].array() <= hi.array()).all()) {
          pinned[i] = 1;
          ++selected;
        }
      }
      if (selected == 0) throw InputError(pin.path + ".box: selects no vertex");
    }
  }
}

}  // namespace

Simulation build_simulation(const Scene& scene) {
  TriMesh mesh = make_mesh(scene.mesh);
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

  State& state = sim.state;
  state.x = std::move(mesh.positions);
  apply_transform(scene.transform, state.x);
  model.pinned.assign(state.x.size(), 0);
  apply_pins(scene.pins, state.x, model.pinned);
  precompute_rest(model);
  if (model.material.bending > 0.0) {
    model.bending = std::make_shared<const BendingModel>(build_bending(
        model.triangles, model.rest_uv, model.material.bending, model.material.bending_warp));
  }
  state.v.assign(state.x.size(), scene.initial_velocity);
  for (size_t i = 0; i < state.v.size(); ++i) {
    if (model.pinned[i]) state.v[i].setZero();
  }
  return sim;
}

}  // namespace tissu
