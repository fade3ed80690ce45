// Model: everything about a simulation that does not change during a run (rest geometry,
// precomputed per-triangle factors, masses, material, the force terms and obstacles the
// scene declared). State: what evolves (positions, velocities, time).
// A step takes `const Model&` and `State&` (see step.h).
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/types.h"
#include "physics/obstacle.h"

namespace tissu {

struct BendingModel;  // physics/bending.h
struct MembraneLayout;  // physics/membrane_layout.h

// Fabric constants. E is the paper's eq. 5 matrix in Voigt order (uu, vv, uv):
// [[weft, coupling, 0], [coupling, warp, 0], [0, 0, shear]].
struct Material {
  std::string name;            // preset name or "custom"
  double density = 0.0;        // areal density rho_A, kg/m^2
  double weft = 0.0;           // C_uu, N/m
  double warp = 0.0;           // C_vv, N/m
  double coupling = 0.0;       // C_uv, N/m
  double shear = 0.0;          // G, N/m
  double bending = 0.0;        // flexural rigidity B, N*m (energy per area B/2 k^2)
  double bending_warp = -1.0;  // optional warp flexural rigidity, N*m; < 0 = same as weft
  double damping = 0.0;        // strain-rate damping time, s: viscous stress = damping * E * de/dt
  // Stiffness along a compressed yarn (weft or warp strain < 0) as a share of the tensile
  // one, (0, 1]: 1 = linear (the paper's), below 1 = a woven fabric buckling at the yarn
  // scale (physics/membrane.h, docs/materials.md).
  double compression_ratio = 1.0;
  Mat3 stiffness() const;      // E, N/m
};

// Rest data of one triangle (eq. 1-2): distribution factors and area.
struct TriangleRest {
  double ru[3];  // r_ua, r_ub, r_uc, 1/m
  double rv[3];  // r_va, r_vb, r_vc, 1/m
  double area;   // rest area A = |d|/2, m^2
};

// Wind (eq. 8, interpreted; see docs/physics.md): each triangle feels
// F = drag * A * ((w(t) - v_tri) . n) n spread equally over its vertices, where n is the
// unit normal and w(t) the wind velocity with optional gusts.
struct Wind {
  Vec3 velocity = Vec3::Zero();  // mean wind velocity, m/s
  double drag = 0.0;             // N*s/m^3, normal pressure per unit normal relative speed
  double gust_amplitude = 0.0;   // fraction of the mean speed
  double gust_period = 1.0;      // s
  Vec3 at(double t) const;       // wind velocity at time t, m/s
};

struct PositionCorrection {
  double threshold = 0.0;  // m
  int iterations = 1;
};

// Cloth against cloth (physics/cloth_contact.h): the distance the cloth keeps from itself
// and Coulomb friction between its layers.
struct SelfCollision {
  double thickness = 0.0;  // m
  double friction = 0.0;   // Coulomb coefficient (dimensionless)
};

// Newton and conjugate-gradient settings of the implicit integrators.
enum class LinearSolver {
  Cholesky,        // sparse Cholesky factor of each Newton matrix, as PCG's preconditioner
  BlockJacobiPcg,  // PCG with the 3x3 block-Jacobi preconditioner (no factorization)
  ScalarCholesky,  // a scalar (one unknown per vertex) Cholesky factor, S (x) I3, of each
                   // Newton matrix, factorized at every solve (scalar_preconditioner.h)
  ScaledScalarCholesky,  // the same with the 3x3 block-Jacobi scaling around it
};
// Every linear solver, and its name in scenes (implicit.linear_solver) and benchmarks.
constexpr LinearSolver kLinearSolvers[] = {LinearSolver::Cholesky, LinearSolver::BlockJacobiPcg,
                                           LinearSolver::ScalarCholesky,
                                           LinearSolver::ScaledScalarCholesky};
const char* linear_solver_name(LinearSolver solver);

// What the line search of each Newton iteration measures.
enum class LineSearch {
  Potential,  // the incremental potential (Gast & Schroeder 2014), non-conservative forces
              // frozen at the iterate
  Residual,   // the norm of the step equation's residual
};

// How the implicit solve keeps cloth out of sphere, cylinder, plane and mesh obstacles.
// The cloth against itself (self_collision) is the barrier's with either model.
enum class ContactModel {
  Constraints,  // velocity constraints filtered inside PCG, an active set (contact.h)
  Barrier,      // IPC's log barrier potential with its Hessian (barrier_contact.h)
};

struct ImplicitOptions {
  LinearSolver linear_solver = LinearSolver::Cholesky;
  LineSearch line_search = LineSearch::Potential;
  ContactModel contact = ContactModel::Constraints;
  double barrier_distance = 0.0;   // the barrier's dhat, m; 0: a quarter of the mean rest
                                   // edge (barrier_contact.h)
  double barrier_stiffness_dt = 0.0;  // s: the barrier's kappa is m / this^2; 0: the step dt
  double barrier_damping = 1.0;  // the barrier's normal damping as a ratio of critical
                                 // (dimensionless, >= 0; 1, critical, the default; 0:
                                 // none, the elastic barrier)
  int max_newton_iterations = 8;   // 1 = one Newton iteration (Baraff & Witkin); a step
                                   // the line search shortened, or whose contacts changed
                                   // or slid, gets a few more (docs/implicit.md)
  double newton_tolerance = 1e-2;  // relative residual of the nonlinear step
  double newton_motion_tolerance = 0.0;  // m: Newton also stops after a whole step (no
                                         // contact change) that moved no vertex's end
                                         // position more than this; 0: off
  double cg_tolerance = 1e-3;      // relative residual of each linear solve
};

enum class Integrator {
  ExplicitEuler,    // eq. 9
  SymplecticEuler,  // eq. 10 ("modified Euler")
  BenameurDjedi,    // the paper's algorithm as printed, h F / (2 m)
  BackwardEuler,    // eq. 11, Newton + PCG
  Bdf2,             // second-order backward differentiation
  ImplicitMidpoint, // implicit midpoint rule, Newton + PCG
};
const char* integrator_name(Integrator integrator);
// Explicit Euler, symplectic Euler and the paper's scheme: no solve, a step below the
// stability limit.
bool is_explicit(Integrator integrator);

struct Model {
  // Mesh (V vertices, T triangles).
  TriList triangles;            // (T) vertex ids
  Vec2List rest_uv;             // (V) rest coordinates, m
  std::vector<TriangleRest> rest;  // (T) eq. 1-2 factors
  // The same factors laid out for the vectorised membrane kernel (membrane_simd.h).
  std::shared_ptr<const MembraneLayout> membrane_layout;
  std::vector<double> mass;     // (V) lumped mass, kg (rho_A * area / 3 summed)
  std::vector<double> inv_mass; // (V) 1/kg, 0 for pinned vertices
  std::vector<double> lumped_area;  // (V) one third of the adjacent rest areas, m^2
  std::vector<uint8_t> pinned;  // (V) 1 = position fixed
  Material material;

  // Force terms and constraints the scene declared; absent = not modelled.
  std::optional<Vec3> gravity;          // m/s^2
  std::optional<double> air_damping;    // N*s/m^3 (eq. 7 per unit cloth area)
  std::optional<Wind> wind;
  std::optional<PositionCorrection> position_correction;
  std::vector<Obstacle> obstacles;
  std::optional<SelfCollision> self_collision;
  std::shared_ptr<const BendingModel> bending;  // null when the material has no bending

  // Time stepping.
  Integrator integrator = Integrator::SymplecticEuler;
  double dt = 1e-3;  // s
  double max_speed = 100.0;  // m/s; a faster vertex means the run diverged
  ImplicitOptions implicit;

  // Set anew by every precompute_rest, so caches built from the mesh (a Workspace's force
  // plan) know when they were made for another mesh.
  uint64_t mesh_id = 0;

  int num_vertices() const { return static_cast<int>(rest_uv.size()); }
  int num_triangles() const { return static_cast<int>(triangles.size()); }
};

// The state one (sub)step back, recorded by the implicit integrators: BDF-2, a two-step
// method, builds on it. Part of the state, so a state saved and restored carries it.
struct StepHistory {
  Vec3List x;       // (V) positions at time t, m
  Vec3List v;       // (V) velocities at time t, m/s
  double t = 0.0;   // s
  double dt = 0.0;  // the step size taken from them, s; 0: none recorded
};

struct State {
  Vec3List x;  // (V) positions, m
  Vec3List v;  // (V) velocities, m/s
  double t = 0.0;  // s
  long long step = 0;
  StepHistory previous;  // empty unless an implicit integrator stepped
  bool start_placed = false;  // prepare_start has placed the run's start (step.h)
};

// Builds the rest data (eq. 1-2, and its vectorised layout), lumped masses and areas from a
// mesh and a material, and gives the model a new mesh_id.
// Throws InputError naming the triangle for degenerate rest triangles.
void precompute_rest(Model& model);

// The mean length of the triangles' rest sides (an inner edge counted once per triangle),
// m; 0 without triangles.
double mean_rest_edge(const Model& model);

// The mesh's edges, each once as (a, b) with a < b, in ascending order.
std::vector<std::array<int, 2>> unique_edges(const TriList& triangles);

}  // namespace tissu
