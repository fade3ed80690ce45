// Peirce's cantilever test (ASTM D1388) in Tissu: a strip clamped at one end, bent under its
// own weight, compared with the elastica. Used by the bending tests.
#pragma once

#include <Eigen/Sparse>
#include <cmath>
#include <algorithm>
#include <functional>
#include <memory>
#include <random>
#include <vector>

#include "mesh/generate.h"
#include "mesh/irregular.h"
#include "physics/bending.h"
#include "physics/block_triplets.h"
#include "physics/diagnostics.h"
#include "physics/forces.h"
#include "physics/model.h"

namespace tissu::testing {

// Chord angle (rad, below the horizontal) of the heavy elastica: a strip of length L,
// weight w per length and rigidity B, clamped horizontally at s = 0 and free at s = L, with
// load parameter alpha = w L^3 / B. The slope theta(s) solves B theta'' = -w (L - s) cos theta,
// theta(0) = 0, theta'(L) = 0; found by shooting on theta'(0) with RK4.
inline double elastica_chord_angle(double alpha) {
  const int n = 4000;
  const double ds = 1.0 / n;  // s in units of L
  // Integrates from s = 0 with theta'(0) = k0; returns theta'(1) and the tip (x, y) / L.
  auto shoot = [&](double k0, double* tip_x, double* tip_y) {
    auto rhs = [alpha](double s, const Eigen::Vector4d& y) {
      // y = (theta, theta', x, y)
      return Eigen::Vector4d(y[1], -alpha * (1.0 - s) * std::cos(y[0]), std::cos(y[0]),
                             std::sin(y[0]));
    };
    Eigen::Vector4d y(0.0, k0, 0.0, 0.0);
    for (int i = 0; i < n; ++i) {
      const double s = i * ds;
      const Eigen::Vector4d a = rhs(s, y);
      const Eigen::Vector4d b = rhs(s + ds / 2, y + ds / 2 * a);
      const Eigen::Vector4d c = rhs(s + ds / 2, y + ds / 2 * b);
      const Eigen::Vector4d d = rhs(s + ds, y + ds * c);
      y += ds / 6 * (a + 2 * b + 2 * c + d);
    }
    if (tip_x) *tip_x = y[2];
    if (tip_y) *tip_y = y[3];
    return y[1];
  };
  // theta'(1) rises monotonically with k0 on [0, alpha/2] (alpha/2 is the linear answer,
  // an upper bound since cos theta <= 1): bisect.
  double lo = 0.0, hi = alpha / 2 + 1e-9;
  for (int it = 0; it < 100; ++it) {
    const double mid = (lo + hi) / 2;
    (shoot(mid, nullptr, nullptr) > 0.0 ? hi : lo) = mid;
  }
  double x = 0.0, y = 0.0;
  shoot((lo + hi) / 2, &x, &y);
  return std::atan2(y, x);
}

// A strip meshed in its rest plane: `length` along the strip direction d, `width` across,
// plus a clamped part of `clamp` behind s = 0. rest (u, v) are fabric coordinates; the strip
// runs along d = (cos angle, sin angle) in the fabric plane.
enum class StripMesh {
  UnionJack,     // structured, cell diagonals alternating cell by cell
  OneDiagonal,   // structured, every cell cut along the same diagonal
  Irregular,     // Delaunay, Poisson-disk interior points
};

struct Strip {
  TriList triangles;
  Vec2List st;       // (s along the strip, t across), m
  double length = 0.0, width = 0.0, clamp = 0.0;
};

inline Strip make_strip(StripMesh kind, double length, double width, double cell, int clamp_cells,
                        uint64_t seed = 1) {
  Strip strip;
  strip.length = length;
  strip.width = width;
  strip.clamp = clamp_cells * cell;
  const double total = length + strip.clamp;
  const int nx = static_cast<int>(std::lround(total / cell));
  const int ny = std::max(1, static_cast<int>(std::lround(width / cell)));
  if (kind == StripMesh::Irregular) {
    // Irregular over the free part [0, length]; the clamped part behind it is one row of
    // cells on the boundary points of s = 0 (a clamp is rigid: how it is cut is moot).
    const int nl = static_cast<int>(std::lround(length / cell));
    ConvexDomain domain;
    for (int i = 0; i < nl; ++i) domain.boundary.emplace_back(length * i / nl, 0.0);
    for (int j = 0; j < ny; ++j) domain.boundary.emplace_back(length, width * j / ny);
    for (int i = nl; i > 0; --i) domain.boundary.emplace_back(length * i / nl, width);
    for (int j = ny; j > 0; --j) domain.boundary.emplace_back(0.0, width * j / ny);
    domain.contains = [length, width](const Vec2& p, double margin) {
      return p.x() > margin && p.x() < length - margin && p.y() > margin &&
             p.y() < width - margin;
    };
    const double cell_area = std::sqrt(3.0) / 4 * cell * cell;
    const int interior = std::max(0, static_cast<int>(length * width / cell_area / 2) -
                                         static_cast<int>(domain.boundary.size()) / 2);
    const PlanarTriangulation tri = irregular_triangulation(domain, interior, cell, seed);
    strip.st = tri.points;
    strip.triangles = tri.triangles;
    std::vector<int> edge;  // vertices on s = 0, by t
    for (int i = 0; i < static_cast<int>(strip.st.size()); ++i) {
      if (strip.st[i].x() == 0.0) edge.push_back(i);
    }
    std::sort(edge.begin(), edge.end(),
              [&](int a, int b) { return strip.st[a].y() < strip.st[b].y(); });
    std::vector<int> back;
    for (int i : edge) {
      back.push_back(static_cast<int>(strip.st.size()));
      strip.st.emplace_back(-strip.clamp, strip.st[i].y());
    }
    for (size_t j = 0; j + 1 < edge.size(); ++j) {
      strip.triangles.emplace_back(back[j], edge[j], edge[j + 1]);
      strip.triangles.emplace_back(back[j], edge[j + 1], back[j + 1]);
    }
    return strip;
  }
  for (int j = 0; j <= ny; ++j) {
    for (int i = 0; i <= nx; ++i) strip.st.emplace_back(-strip.clamp + total * i / nx, width * j / ny);
  }
  auto id = [nx](int i, int j) { return j * (nx + 1) + i; };
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const bool flip = kind == StripMesh::UnionJack && (i + j) % 2 == 1;
      if (!flip) {
        strip.triangles.emplace_back(id(i, j), id(i + 1, j), id(i + 1, j + 1));
        strip.triangles.emplace_back(id(i, j), id(i + 1, j + 1), id(i, j + 1));
      } else {
        strip.triangles.emplace_back(id(i, j), id(i + 1, j), id(i, j + 1));
        strip.triangles.emplace_back(id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
      }
    }
  }
  return strip;
}

struct CantileverSetup {
  double bending_weft = 1e-5;   // N*m
  double bending_warp = -1.0;   // N*m, < 0: isotropic
  double density = 0.1;         // kg/m^2
  double gravity = 9.81;        // m/s^2
  double fabric_angle = 0.0;    // rad: the strip's direction in the fabric (u, v) plane
  double mesh_angle = 0.0;      // rad: the strip's direction in the world x-y plane
};

struct CantileverResult {
  double chord_angle = 0.0;  // rad, from the clamp edge to the mean tip
  int newton_iterations = 0;
  bool converged = false;
};

// Static equilibrium of the strip under gravity (-z), clamped (pinned) for s <= 0; Newton on
// the potential energy (membrane + bending + gravity) with gravity ramped in increments.
inline CantileverResult solve_cantilever(const Strip& strip, const CantileverSetup& setup) {
  Model model;
  const Vec2 d(std::cos(setup.fabric_angle), std::sin(setup.fabric_angle));
  const Vec2 n(-d.y(), d.x());
  const Vec2 dw(std::cos(setup.mesh_angle), std::sin(setup.mesh_angle));
  const Vec2 nw(-dw.y(), dw.x());
  const int V = static_cast<int>(strip.st.size());
  Vec3List x(V);
  for (int i = 0; i < V; ++i) {
    const Vec2& p = strip.st[i];
    model.rest_uv.push_back(p.x() * d + p.y() * n);
    const Vec2 w = p.x() * dw + p.y() * nw;
    x[i] = Vec3(w.x(), w.y(), 0.0);
  }
  model.triangles = strip.triangles;
  Material& mat = model.material;
  mat.name = "cantilever";
  mat.density = setup.density;
  mat.weft = mat.warp = 2000.0;  // N/m: stiff enough to be inextensible here
  mat.coupling = 400.0;
  mat.shear = 800.0;
  mat.bending = setup.bending_weft;
  mat.bending_warp = setup.bending_warp;
  model.pinned.assign(V, 0);
  for (int i = 0; i < V; ++i) model.pinned[i] = strip.st[i].x() <= 1e-9 ? 1 : 0;
  precompute_rest(model);
  model.bending = std::make_shared<const BendingModel>(
      build_bending(model.triangles, model.rest_uv, mat.bending, mat.bending_warp, model.pinned));

  CantileverResult result;
  const Vec3List zero_v(V, Vec3::Zero());
  const int ramps = 4;
  for (int ramp = 1; ramp <= ramps; ++ramp) {
    model.gravity = Vec3(0.0, 0.0, -setup.gravity * ramp / ramps);
    auto potential = [&](const Vec3List& y) {
      return elastic_energy(model, y) + gravity_potential(model, y);
    };
    for (int it = 0; it < 60; ++it) {
      Vec3List f(V, Vec3::Zero());
      compute_forces(model, x, zero_v, 0.0, f);
      Eigen::VectorXd rhs(3 * V);
      double fnorm = 0.0;  // largest force per mass on a free vertex, m/s^2
      for (int i = 0; i < V; ++i) {
        for (int c = 0; c < 3; ++c) rhs[3 * i + c] = model.pinned[i] ? 0.0 : f[i][c];
        if (!model.pinned[i]) fnorm = std::max(fnorm, f[i].norm() / model.mass[i]);
      }
      if (fnorm < 1e-3 * setup.gravity) break;  // round-off: about 5e-4 g here
      // Exact Jacobian first (fast near the answer); the definite (projected) one when the
      // exact step is not a descent direction.
      Eigen::VectorXd dx;
      for (bool project : {false, true}) {
        BlockTriplets dfdx, dfdv;
        compute_force_jacobian(model, x, zero_v, 0.0, project, dfdx, dfdv);
        Eigen::SparseMatrix<double> K = -dfdx.to_sparse(V);
        for (int k = 0; k < K.outerSize(); ++k) {  // pinned rows and columns: identity
          for (Eigen::SparseMatrix<double>::InnerIterator e(K, k); e; ++e) {
            if (model.pinned[e.row() / 3] || model.pinned[e.col() / 3]) e.valueRef() = 0.0;
          }
        }
        Eigen::SparseMatrix<double> I(3 * V, 3 * V);
        for (int i = 0; i < V; ++i) {
          for (int c = 0; c < 3; ++c) I.insert(3 * i + c, 3 * i + c) = model.pinned[i] ? 1.0 : 0.0;
        }
        K += I;
        Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(K);
        dx = solver.solve(rhs);
        if (solver.info() == Eigen::Success && dx.allFinite() && dx.dot(rhs) > 0.0 &&
            (solver.vectorD().array() > 0.0).all()) {
          break;
        }
      }
      const double p0 = potential(x);
      const double round_off = 1e-12 * (std::abs(elastic_energy(model, x)) + std::abs(gravity_potential(model, x)));
      double step = 1.0;
      Vec3List trial(V);
      for (int ls = 0; ls < 30; ++ls, step *= 0.5) {
        for (int i = 0; i < V; ++i) trial[i] = x[i] + step * dx.segment<3>(3 * i);
        if (potential(trial) <= p0 + round_off) break;
      }
      x = trial;
      ++result.newton_iterations;
    }
  }
  // Chord from the clamp edge (mid-width) to the mean of the tip vertices.
  Vec3 root = Vec3::Zero(), tip = Vec3::Zero();
  int nr = 0, nt = 0;
  for (int i = 0; i < V; ++i) {
    if (std::abs(strip.st[i].x()) < 1e-9) root += x[i], ++nr;
    if (std::abs(strip.st[i].x() - strip.length) < 1e-9) tip += x[i], ++nt;
  }
  root /= nr;
  tip /= nt;
  const Vec3 chord = tip - root;
  result.chord_angle = std::atan2(-chord.z(), std::hypot(chord.x(), chord.y()));
  Vec3List f(V, Vec3::Zero());
  compute_forces(model, x, zero_v, 0.0, f);
  double fnorm = 0.0;
  for (int i = 0; i < V; ++i) {
    if (!model.pinned[i]) fnorm = std::max(fnorm, f[i].norm() / model.mass[i]);
  }
  result.converged = fnorm < 2e-3 * setup.gravity;
  return result;
}

}  // namespace tissu::testing
