// Cusick's drape test (BS 5058, ISO 9073-9) in Tissu: a disc of fabric laid flat on a
// smaller support disc sags under gravity into folds; the drape coefficient is the share
// of the overhanging ring that its shadow still covers. Used by the drape tests.
#pragma once

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "mesh/generate.h"
#include "physics/bending.h"
#include "physics/diagnostics.h"
#include "physics/forces.h"
#include "physics/implicit.h"
#include "physics/materials.h"
#include "physics/membrane_layout.h"
#include "physics/model.h"
#include "physics/step.h"

namespace tissu::testing {

// Area (m^2) of the union of the triangles' shadows on the x-y plane: the cells of a
// square grid of side `cell` (m) whose centres lie in some shadow, counted once. A cell
// that the outline crosses is counted whole or not at all, so the error is at most the
// area of the cells along the outline, sqrt(2) * cell * (outline length), and in practice
// far less (the errors along the outline cancel; measured in the drape tests).
inline double projected_area(const Vec3List& x, const TriList& triangles, double cell) {
  double lo_x = x[0].x(), hi_x = lo_x, lo_y = x[0].y(), hi_y = lo_y;
  for (const Vec3& p : x) {
    lo_x = std::min(lo_x, p.x()), hi_x = std::max(hi_x, p.x());
    lo_y = std::min(lo_y, p.y()), hi_y = std::max(hi_y, p.y());
  }
  const int nx = static_cast<int>(std::ceil((hi_x - lo_x) / cell)) + 1;
  const int ny = static_cast<int>(std::ceil((hi_y - lo_y) / cell)) + 1;
  std::vector<uint8_t> covered(static_cast<size_t>(nx) * ny, 0);
  for (const Tri& t : triangles) {
    const Vec2 a(x[t[0]].x(), x[t[0]].y()), b(x[t[1]].x(), x[t[1]].y()),
        c(x[t[2]].x(), x[t[2]].y());
    const double area2 = (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
    if (area2 == 0.0) continue;  // seen edge-on: no shadow of its own
    const double s = area2 > 0.0 ? 1.0 : -1.0;
    // Cell (i, j) has its centre at lo + (i + 1/2, j + 1/2) cell: the cells whose centres
    // may lie in the triangle's bounding box.
    auto first = [cell](double lo, double v) {
      return std::max(0, static_cast<int>(std::floor((v - lo) / cell - 0.5)));
    };
    auto last = [cell](double lo, double v, int n) {
      return std::min(n - 1, static_cast<int>(std::ceil((v - lo) / cell - 0.5)));
    };
    const int i0 = first(lo_x, std::min({a.x(), b.x(), c.x()}));
    const int i1 = last(lo_x, std::max({a.x(), b.x(), c.x()}), nx);
    const int j0 = first(lo_y, std::min({a.y(), b.y(), c.y()}));
    const int j1 = last(lo_y, std::max({a.y(), b.y(), c.y()}), ny);
    auto side = [s](const Vec2& p, const Vec2& q, const Vec2& r) {
      return s * ((q - p).x() * (r - p).y() - (q - p).y() * (r - p).x());
    };
    for (int j = j0; j <= j1; ++j) {
      for (int i = i0; i <= i1; ++i) {
        const Vec2 centre(lo_x + (i + 0.5) * cell, lo_y + (j + 0.5) * cell);
        if (side(a, b, centre) >= 0.0 && side(b, c, centre) >= 0.0 && side(c, a, centre) >= 0.0) {
          covered[static_cast<size_t>(j) * nx + i] = 1;
        }
      }
    }
  }
  size_t count = 0;
  for (uint8_t c : covered) count += c;
  return static_cast<double>(count) * cell * cell;
}

// Waves of the rim's height around the disc: the rim vertices (|rest| = radius) by angle,
// and half the number of times their height crosses its mean.
inline int rim_waves(const Vec2List& rest, const Vec3List& x, double radius) {
  std::vector<std::pair<double, double>> rim;  // (angle, height)
  for (size_t i = 0; i < rest.size(); ++i) {
    if (rest[i].norm() > radius * (1.0 - 1e-9)) {
      rim.emplace_back(std::atan2(x[i].y(), x[i].x()), x[i].z());
    }
  }
  std::sort(rim.begin(), rim.end());
  double mean = 0.0;
  for (const auto& p : rim) mean += p.second / rim.size();
  int crossings = 0;
  for (size_t k = 0; k < rim.size(); ++k) {
    const double a = rim[k].second - mean, b = rim[(k + 1) % rim.size()].second - mean;
    crossings += (a < 0.0) != (b < 0.0) ? 1 : 0;
  }
  return crossings / 2;
}

struct DrapeSetup {
  Material material;
  double radius = 0.15;          // m: the fabric disc, 30 cm across
  double support_radius = 0.09;  // m: the support disc, 18 cm across
  int triangles = 1500;          // of the fabric disc's mesh
  bool irregular = true;
  std::optional<DiskGrading> grading;  // a graded disc (generate.h; `irregular` unused)
  uint64_t seed = 1;
  double mesh_angle = 0.0;  // rad: the mesh turned about the vertical axis (the fabric's
                            // weft and warp, the start and gravity stay where they are)
  double dt = 0.01;             // s, backward Euler
  double damping_rate = 20.0;   // 1/s: air damping per unit mass (air_damping / density)
  double start_amplitude = 5e-4;  // m: the flat start's ripple at the rim, breaks symmetry
  int start_folds = 0;          // > 0: the ripple is this one angular mode
  double rest_speed = 1e-3;     // m/s: at rest when the RMS speed stays below this ...
  double rest_time = 0.2;       // s: ... for this long
  double max_time = 6.0;        // s: gives up after this much simulated time
  double raster_cell = 2e-4;    // m: grid of projected_area
  double newton_tolerance = 1e-8;  // of each backward Euler step
  bool clamp = true;  // the support's triangles are a clamp in the bending model (bending.h)
  // Membrane stiffness times this in the first ring outside the clamp (triangles with
  // pinned and free corners): an experiment on locking at the support's edge.
  double clamp_ring_membrane = 1.0;
  int trace_every = 0;  // > 0: prints t, DC and the kinetic energy every so many steps
};

struct DrapeResult {
  double coefficient = 0.0;  // drape coefficient DC
  double projected = 0.0;    // m^2
  bool at_rest = false;
  double time = 0.0;         // s, simulated to rest
  long long steps = 0;
  double seconds = 0.0;      // wall-clock time of the run, s (reported, never asserted)
  int vertices = 0, triangles = 0;
  double mean_edge = 0.0;    // m
  double bending_energy = 0.0, membrane_energy = 0.0, gravity_energy = 0.0;  // J, at rest
  double force_residual = 0.0;  // largest force per weight on a free vertex at the end
  double kinetic_energy = 0.0;  // J, at the end
  int folds = 0;             // waves of the rim's height around the disc
  Vec3List x;                // the draped shape
  TriList mesh;
};

// The flat start's height (m) at (x, y): zero on the support, a ripple over the overhang
// that grows as the square of the distance from the support's rim: the angular mode
// start_folds, or else a sum of modes 3..12 of equal amplitude and spread phases (then the
// fold count the drape settles in varies with the mesh, docs/bending.md). It is fixed in
// the world, so turning the mesh leaves it unchanged.
inline double cusick_start_height(double x, double y, const DrapeSetup& s) {
  const double r = std::hypot(x, y);
  if (r <= s.support_radius) return 0.0;
  const double q = (r - s.support_radius) / (s.radius - s.support_radius);
  const double theta = std::atan2(y, x);
  if (s.start_folds > 0) return s.start_amplitude * q * q * std::cos(s.start_folds * theta);
  double sum = 0.0;
  for (int n = 3; n <= 12; ++n) sum += std::cos(n * theta + 2.39996 * n);
  return s.start_amplitude * q * q * sum / 10.0;
}

// A preset with its bending length's rigidity B = rho_A g c^3 in every direction (the
// geometric mean of its weft and warp B), times `rigidity_factor`. An orthotropic fabric
// has the symmetry of a rectangle, which nine folds do not share: its drape then has
// several nine-fold rests whose coefficients differ by up to 0.03 (docs/bending.md); the
// isotropic one has one.
inline Material isotropic_preset(const std::string& preset, double rigidity_factor = 1.0) {
  Material m = *material_preset(preset);
  m.bending = m.bending_warp = rigidity_factor * std::sqrt(m.bending * m.bending_warp);
  if (rigidity_factor != 1.0) m.name += " x" + std::to_string(static_cast<int>(rigidity_factor));
  return m;
}

// The drape tests' run: released from a flat start rippled with nine folds of 3 mm at the
// rim (cotton's own fold count at fine meshes), backward Euler at 50 Hz.
inline DrapeSetup nine_fold_drape(const Material& material, int triangles) {
  DrapeSetup s;
  s.material = material;
  s.triangles = triangles;
  s.start_folds = 9;
  s.start_amplitude = 3e-3;
  s.dt = 0.02;
  s.newton_tolerance = 1e-5;
  return s;
}

// Drape coefficient of the shape x of the disc meshed by `triangles`.
inline double drape_coefficient(const DrapeSetup& s, const Vec3List& x, const TriList& triangles) {
  const double support = kPi * s.support_radius * s.support_radius;
  const double disc = kPi * s.radius * s.radius;
  return (projected_area(x, triangles, s.raster_cell) - support) / (disc - support);
}

// Cusick's grading: edges `fine_ratio` times the others over the 2.5 cm beyond the
// support's edge, where the folds rise out of the clamp (docs/bending.md), blending into
// the coarse edge over 1.5 cm on either side.
inline DiskGrading cusick_grading(const DrapeSetup& s, double fine_ratio) {
  return DiskGrading{s.support_radius, s.support_radius + 0.025, fine_ratio, 0.015};
}

// The fabric disc's mesh, flat, with a circle of vertices at the support's edge.
inline TriMesh drape_mesh(const DrapeSetup& s) {
  if (s.grading) return generate_disk(s.radius, s.triangles, s.seed, s.support_radius, *s.grading);
  return generate_disk(s.radius, s.triangles, s.irregular, s.seed, s.support_radius);
}

// Lays the disc flat on the support (vertices within the support radius pinned: the
// support and its clamp), releases it under gravity and runs backward Euler with air
// damping until it is at rest.
inline DrapeResult run_cusick(const DrapeSetup& s) {
  const auto wall_start = std::chrono::steady_clock::now();
  TriMesh mesh = drape_mesh(s);
  const double c = std::cos(s.mesh_angle), sn = std::sin(s.mesh_angle);
  Model model;
  State state;
  for (const Vec2& p : mesh.rest_uv) {
    const Vec2 w(c * p.x() - sn * p.y(), sn * p.x() + c * p.y());
    model.rest_uv.push_back(w);
    state.x.emplace_back(w.x(), w.y(), cusick_start_height(w.x(), w.y(), s));
  }
  model.triangles = mesh.triangles;
  model.material = s.material;
  model.gravity = Vec3(0.0, 0.0, -9.80665);
  model.air_damping = s.damping_rate * s.material.density;
  model.integrator = Integrator::BackwardEuler;
  model.dt = s.dt;
  // Newton to round-off: with the default tolerance (1e-2 of gravity's impulse) a step
  // that starts at rest stays at rest while the forces are below a hundredth of the
  // weight, and the cloth stops short of its equilibrium.
  model.implicit.newton_tolerance = s.newton_tolerance;
  model.implicit.max_newton_iterations = 20;
  const int V = model.num_vertices();
  model.pinned.assign(V, 0);
  for (int i = 0; i < V; ++i) {
    model.pinned[i] = model.rest_uv[i].norm() <= s.support_radius * (1.0 + 1e-9) ? 1 : 0;
  }
  precompute_rest(model);
  if (s.clamp_ring_membrane != 1.0) {
    // The membrane weighs each triangle by its rest area; the masses are already lumped.
    for (int t = 0; t < model.num_triangles(); ++t) {
      const Tri& tri = model.triangles[t];
      const int pins = model.pinned[tri[0]] + model.pinned[tri[1]] + model.pinned[tri[2]];
      if (pins > 0 && pins < 3) model.rest[t].area *= s.clamp_ring_membrane;
    }
    model.membrane_layout = std::make_shared<const MembraneLayout>(
        build_membrane_layout(model.triangles, model.rest, model.mesh_id));
  }
  model.bending = std::make_shared<const BendingModel>(
      build_bending(model.triangles, model.rest_uv, s.material.bending, s.material.bending_warp,
                    s.clamp ? model.pinned : std::vector<uint8_t>{}));
  state.v.assign(V, Vec3::Zero());

  DrapeResult result;
  result.vertices = V;
  result.triangles = model.num_triangles();
  double edges = 0.0;
  for (const Tri& t : model.triangles) {
    for (int k = 0; k < 3; ++k) {
      edges += (model.rest_uv[t[k]] - model.rest_uv[t[(k + 1) % 3]]).norm();
    }
  }
  result.mean_edge = edges / (3.0 * model.num_triangles());

  const double mass = total_mass(model);
  Workspace ws;
  double calm = 0.0;  // s the run has been below rest_speed
  while (state.t < s.max_time) {
    if (step(model, state, ws)) break;  // diverged: not at rest
    ++result.steps;
    const double speed = std::sqrt(2.0 * kinetic_energy(model, state.v) / mass);
    if (s.trace_every > 0 && result.steps % s.trace_every == 0) {
      std::printf("    t %.2f s: DC %.4f, kinetic energy %.3e J, RMS speed %.2e m/s\n", state.t,
                  drape_coefficient(s, state.x, model.triangles), kinetic_energy(model, state.v),
                  speed);
      std::fflush(stdout);
    }
    calm = speed < s.rest_speed ? calm + s.dt : 0.0;
    if (calm >= s.rest_time - 1e-12) {
      result.at_rest = true;
      break;
    }
  }
  result.time = state.t;
  result.projected = projected_area(state.x, model.triangles, s.raster_cell);
  result.coefficient = drape_coefficient(s, state.x, model.triangles);
  result.kinetic_energy = kinetic_energy(model, state.v);
  Vec3List f(V, Vec3::Zero());
  compute_forces(model, state.x, Vec3List(V, Vec3::Zero()), state.t, f);
  for (int i = 0; i < V; ++i) {
    if (model.pinned[i]) continue;
    const double per_weight = f[i].norm() / (model.mass[i] * model.gravity->norm());
    result.force_residual = std::max(result.force_residual, per_weight);
  }
  result.bending_energy = bending_energy(*model.bending, state.x);
  result.membrane_energy = elastic_energy(model, state.x) - result.bending_energy;
  result.gravity_energy = gravity_potential(model, state.x);
  result.folds = rim_waves(model.rest_uv, state.x, s.radius);
  result.x = state.x;
  result.mesh = model.triangles;
  result.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  return result;
}

}  // namespace tissu::testing
