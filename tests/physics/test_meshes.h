// Small meshes built inside the physics tests (no dependency on the mesh generator).
#pragma once

#include <cmath>
#include <random>

#include "physics/materials.h"
#include "physics/model.h"

namespace tissu::testing {

// A w x h rectangle of nx x ny cells in the x-y plane, rest (u, v) = (x, y); interior
// vertices jittered by up to `jitter` of a cell and diagonals chosen at random, so the
// triangles are irregular.
inline Model grid_model(double w, double h, int nx, int ny, double jitter, unsigned seed,
                        Vec3List* positions) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  Model m;
  for (int j = 0; j <= ny; ++j) {
    for (int i = 0; i <= nx; ++i) {
      Vec2 p(w * i / nx - w / 2, h * j / ny - h / 2);
      if (i > 0 && i < nx && j > 0 && j < ny) {
        p += Vec2(uniform(rng) * jitter * w / nx, uniform(rng) * jitter * h / ny);
      }
      m.rest_uv.push_back(p);
    }
  }
  auto id = [nx](int i, int j) { return j * (nx + 1) + i; };
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      if (rng() % 2) {
        m.triangles.emplace_back(id(i, j), id(i + 1, j), id(i + 1, j + 1));
        m.triangles.emplace_back(id(i, j), id(i + 1, j + 1), id(i, j + 1));
      } else {
        m.triangles.emplace_back(id(i, j), id(i + 1, j), id(i, j + 1));
        m.triangles.emplace_back(id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
      }
    }
  }
  if (positions) {
    positions->clear();
    for (const Vec2& p : m.rest_uv) positions->emplace_back(p.x(), p.y(), 0.0);
  }
  return m;
}

// An anisotropic fabric-like material (N/m, kg/m^2).
inline Material test_material() {
  Material mat;
  mat.name = "test";
  mat.density = 0.2;
  mat.weft = 800.0;
  mat.warp = 500.0;
  mat.coupling = 120.0;
  mat.shear = 60.0;
  return mat;
}

// A flat cotton sheet (membrane only, no bending model to build) of nx x ny irregular cells
// and sides w x h (m), centred at the origin in the x-y plane, at rest, under gravity
// (9.81 m/s^2 along -z), stepped by `integrator` at dt (s).
struct Sheet {
  Model model;
  State state;
};

inline Sheet cotton_rectangle(double w, double h, int nx, int ny, Integrator integrator,
                              double dt, unsigned seed = 3) {
  Sheet s;
  Vec3List x;
  s.model = grid_model(w, h, nx, ny, 0.25, seed, &x);
  s.model.material = *material_preset("cotton");
  s.model.material.bending = 0.0;
  s.model.gravity = Vec3(0, 0, -9.81);
  s.model.integrator = integrator;
  s.model.dt = dt;
  precompute_rest(s.model);
  s.state.x = x;
  s.state.v.assign(x.size(), Vec3::Zero());
  return s;
}

// The square one: nx x nx cells, side `size` (m).
inline Sheet cotton_sheet(double size, int nx, Integrator integrator, double dt,
                          unsigned seed = 3) {
  return cotton_rectangle(size, size, nx, nx, integrator, dt, seed);
}

// An obstacle of the given kind (a cylinder's half length equals its radius).
inline Obstacle make_obstacle(ObstacleKind kind, const Vec3& center, const Vec3& axis,
                              double radius, double friction, double thickness) {
  Obstacle ob;
  ob.kind = kind;
  ob.center = center;
  ob.axis = axis.normalized();
  ob.radius = radius;
  ob.half_length = radius;
  ob.friction = friction;
  ob.thickness = thickness;
  return ob;
}

// Positions (m) of a stretched, sheared sheet folded out of plane with per-vertex noise, and
// random velocities (m/s, up to 0.3 per coordinate), from rest coordinates (m): every strain
// and strain-rate component is non-zero.
inline void deformed_moving(const Vec2List& rest_uv, unsigned seed, Vec3List& x, Vec3List& v) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  x.clear();
  v.clear();
  for (const Vec2& p : rest_uv) {
    x.emplace_back(1.03 * p.x() + 0.02 * p.y() + 1e-4 * u(rng), 0.98 * p.y() + 1e-4 * u(rng),
                   0.05 * std::sin(6.0 * p.x()) + 1e-4 * u(rng));
    v.emplace_back(0.3 * u(rng), 0.3 * u(rng), 0.3 * u(rng));
  }
}

}  // namespace tissu::testing
