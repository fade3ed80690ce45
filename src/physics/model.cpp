#include "physics/model.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <string>

#include "core/error.h"
#include "physics/membrane_layout.h"

namespace tissu {

Mat3 Material::stiffness() const {
  Mat3 e;
  e << weft, coupling, 0.0,  //
      coupling, warp, 0.0,   //
      0.0, 0.0, shear;
  return e;
}

Vec3 Wind::at(double t) const {
  if (gust_amplitude == 0.0) return velocity;
  // Gusts: two incommensurate sines so the pattern does not repeat exactly (deterministic).
  const double w = 2.0 * M_PI / gust_period;
  const double g = 0.7 * std::sin(w * t) + 0.3 * std::sin(2.718281828 * w * t + 1.0);
  return velocity * (1.0 + gust_amplitude * g);
}

const char* integrator_name(Integrator integrator) {
  switch (integrator) {
    case Integrator::ExplicitEuler: return "explicit_euler";
    case Integrator::SymplecticEuler: return "symplectic_euler";
    case Integrator::BenameurDjedi: return "benameur_djedi";
    case Integrator::BackwardEuler: return "backward_euler";
    case Integrator::Bdf2: return "bdf2";
    case Integrator::ImplicitMidpoint: return "implicit_midpoint";
  }
  return "unknown";
}

bool is_explicit(Integrator integrator) {
  return integrator == Integrator::ExplicitEuler || integrator == Integrator::SymplecticEuler ||
         integrator == Integrator::BenameurDjedi;
}

const char* linear_solver_name(LinearSolver solver) {
  switch (solver) {
    case LinearSolver::Cholesky: return "cholesky";
    case LinearSolver::BlockJacobiPcg: return "block_jacobi_pcg";
    case LinearSolver::ScalarCholesky: return "scalar_cholesky";
    case LinearSolver::ScaledScalarCholesky: return "scaled_scalar_cholesky";
  }
  return "unknown";
}

// Eq. 1-2 of the paper: distribution factors r_u, r_v and the rest area of each triangle;
// lumped masses rho_A * A / 3 per corner.
void precompute_rest(Model& model) {
  static std::atomic<uint64_t> last_mesh_id{0};
  model.mesh_id = ++last_mesh_id;
  const int n = model.num_vertices();
  model.rest.resize(model.triangles.size());
  model.mass.assign(n, 0.0);
  model.lumped_area.assign(n, 0.0);
  for (size_t t = 0; t < model.triangles.size(); ++t) {
    const Tri& tri = model.triangles[t];
    const Vec2& a = model.rest_uv[tri[0]];
    const Vec2& b = model.rest_uv[tri[1]];
    const Vec2& c = model.rest_uv[tri[2]];
    const double d = a.x() * (b.y() - c.y()) + b.x() * (c.y() - a.y()) + c.x() * (a.y() - b.y());
    const double scale = std::max({(b - a).squaredNorm(), (c - a).squaredNorm(), 1e-300});
    if (!(std::fabs(d) > 1e-12 * scale)) {
      throw InputError("triangle " + std::to_string(t) + ": zero rest area in (u, v)");
    }
    TriangleRest& r = model.rest[t];
    r.ru[0] = (b.y() - c.y()) / d;
    r.ru[1] = (c.y() - a.y()) / d;
    r.ru[2] = (a.y() - b.y()) / d;
    r.rv[0] = (c.x() - b.x()) / d;
    r.rv[1] = (a.x() - c.x()) / d;
    r.rv[2] = (b.x() - a.x()) / d;
    r.area = std::fabs(d) / 2.0;
    for (int k = 0; k < 3; ++k) model.lumped_area[tri[k]] += r.area / 3.0;
  }
  model.inv_mass.assign(n, 0.0);
  if (model.pinned.size() != static_cast<size_t>(n)) model.pinned.assign(n, 0);
  for (int i = 0; i < n; ++i) {
    model.mass[i] = model.material.density * model.lumped_area[i];
    model.inv_mass[i] = (model.pinned[i] || model.mass[i] <= 0.0) ? 0.0 : 1.0 / model.mass[i];
  }
  model.membrane_layout = std::make_shared<const MembraneLayout>(
      build_membrane_layout(model.triangles, model.rest, model.mesh_id));
}

double mean_rest_edge(const Model& model) {
  double edges = 0.0;  // m
  for (const Tri& tri : model.triangles) {
    for (int e = 0; e < 3; ++e) edges += (model.rest_uv[tri[e]] - model.rest_uv[tri[(e + 1) % 3]]).norm();
  }
  return model.num_triangles() > 0 ? edges / (3.0 * model.num_triangles()) : 0.0;
}

std::vector<std::array<int, 2>> unique_edges(const TriList& triangles) {
  std::vector<std::array<int, 2>> edges;
  edges.reserve(3 * triangles.size());
  for (const Tri& t : triangles) {
    for (int k = 0; k < 3; ++k) {
      const int a = t[k], b = t[(k + 1) % 3];
      edges.push_back({std::min(a, b), std::max(a, b)});
    }
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  return edges;
}

}  // namespace tissu
