// Contact of cloth vertices with analytic obstacles (sphere, cylinder, plane) as a barrier
// potential inside an implicit step, the opt-in alternative to the constraints of
// contact.h (scene key "implicit": {"contact": "barrier"}; docs/implicit.md, "A barrier
// instead of constraints").
//
// IPC's log barrier (Li et al. 2020, eq. 6) on each vertex's gap d = distance to the
// surface - the obstacle's thickness (m):
//   b(d) = -kappa (d - dhat)^2 ln(d / dhat)   for 0 < d < dhat,   0 for d >= dhat   (J)
// with dhat = a quarter of the mean rest edge or the scene's (barrier_distance) and kappa = m / dt^2 per vertex (vertex mass m, the scene's
// step dt): the barrier's stiffness b'' beta^2 is then a few times the vertex's mass block,
// so the step's matrix stays as well conditioned as without contact, and a resting vertex
// settles a fraction of dhat from the surface. Its gradient enters the step equation, its
// Hessian (the PSD part b'' n n^T; the curvature part b' Hd is negative semi-definite on a
// convex obstacle and is left out) the step's matrix, its energy the line search's
// incremental potential. The line search never goes past 0.9 of the step at which a
// vertex's straight path first reaches d = 0 (largest_step), so no vertex ends inside.
// Friction is IPC's lagged smoothed Coulomb friction (SlidingFriction, contact.h) with the
// barrier's normal force at the start of the step (and the damping's impulse that stopped
// a landing in the step before: LandingImpulse) as the normal impulse, for vertices
// against obstacles and between the layers of a self pair. A normal damping
// inside the band (NormalDamping) makes a landing inelastic.
// Tests: tests/physics/barrier_contact_test.cpp.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <functional>
#include <vector>

#include "core/types.h"
#include "physics/contact.h"
#include "physics/linear_solver.h"
#include "physics/mesh_barrier.h"
#include "physics/model.h"
#include "physics/obstacle.h"
#include "physics/self_barrier.h"

namespace tissu {

class SystemMatrix;

// The barrier acts below dhat = this fraction of the mesh's mean rest edge (m).
constexpr double kBarrierEdgeFraction = 0.25;
// The line search stops at this fraction of the step that would reach d = 0 (IPC: 0.8-0.9).
constexpr double kBarrierStepFraction = 0.9;

// b(d), b'(d), b''(d) of the log barrier above for kappa (kg/s^2 = J/m^2) and dhat (m):
// J, N and N/m. b is +infinity for d <= 0 and 0 for d >= dhat.
double barrier_energy(double d, double dhat, double kappa);
double barrier_derivative(double d, double dhat, double kappa);
double barrier_second_derivative(double d, double dhat, double kappa);

// The gap of point p to a placed sphere, cylinder or plane: d = signed distance -
// thickness (m), its gradient (the outward normal) and its Hessian (the curvature of the
// distance, 1/m; positive semi-definite outside a convex obstacle).
struct Gap {
  double d = 0.0;
  Vec3 normal = Vec3::UnitZ();
  Mat3 curvature = Mat3::Zero();
  Vec3 surface_velocity = Vec3::Zero();  // m/s
};
Gap obstacle_gap(const PlacedObstacle& obstacle, const Vec3& p);
// Its d alone, the same bits, for the many vertices far from every obstacle. A mesh answers
// gaps beyond `reach` (m) with a lower bound >= reach.
double gap_distance(const PlacedObstacle& obstacle, const Vec3& p, double reach = INFINITY);

// The barrier of one vertex at p against one obstacle: energy (J), gradient (N) and Hessian
// (N/m), exact or (psd) with the curvature part left out.
struct BarrierTerm {
  double energy = 0.0;
  Vec3 gradient = Vec3::Zero();
  Mat3 hessian = Mat3::Zero();
};
BarrierTerm vertex_barrier(const PlacedObstacle& obstacle, const Vec3& p, double kappa,
                           double dhat, bool psd);

// The barrier's normal damping (docs/implicit.md, "A barrier instead of constraints"): a
// vertex within dhat of an obstacle feels f = -c ((v - v_s) . n) n (N), v its velocity,
// v_s the surface's and n the normal (m/s, unit), with c = 2 zeta sqrt(m b''(d)) (kg/s):
// zeta (model.implicit.barrier_damping) times the critical damping of its mass m (kg) on
// the barrier's normal spring b''(d) (N/m). It vanishes with b'' at d = dhat and is
// linear in v at a fixed point; its power -f . (v - v_s) = c ((v - v_s) . n)^2 is never
// negative, so it only takes energy. Landing compresses the barrier; without the damping
// the barrier gives that energy back (a bounce that BDF-2 and the midpoint rule do not damp).
struct NormalDamping {
  Vec3 normal = Vec3::UnitZ();
  Vec3 surface_velocity = Vec3::Zero();  // m/s
  double coefficient = 0.0;              // c, kg/s

  Vec3 force(const Vec3& v) const;       // f(v), N
  Mat3 velocity_jacobian() const;        // df/dv = -c n n^T, kg/s
  double dissipation(const Vec3& v) const;  // -f . (v - v_s) >= 0, W
  // 1/2 c ((v - v_s) . n)^2 (kg m^2/s^3): the incremental potential's term is beta times it,
  // whose gradient in v is -beta f.
  double potential(const Vec3& v) const;
};
// The largest h c / m of the damping in a step whose end positions move by h (s) per unit
// of velocity (beta_end). Near the surface c grows like 1/d, as the barrier's force does,
// so a vertex moving away from the surface faster than about dhat / (2 zeta dt) (kappa =
// m / dt^2) is held back by a damping stronger than the barrier at every gap: the solve
// presses it ever closer, with c ever larger, until the step diverges (BDF-2 on the demo at
// 1/60 s; docs/implicit.md). Capped, the damping's force stays below kMaxStepDamping m |u| /
// h (u the normal velocity relative to the surface) while the barrier's grows without
// bound. At 16 one backward Euler step already takes 94% of u; the cap acts below a gap of
// about zeta (h / dt) dhat / 7 and vanishes as h does.
constexpr double kMaxStepDamping = 16.0;

// The damping of a vertex of mass m (kg) at p against an obstacle, for kappa (kg/s^2),
// dhat (m) and the ratio zeta to critical damping: zero coefficient for d >= dhat or d <= 0.
NormalDamping vertex_damping(const PlacedObstacle& obstacle, const Vec3& p, double kappa,
                             double mass, double dhat, double zeta);

// The first t in [0, 1] at which p + t u reaches d = 0 of the obstacle, 1 if it never does
// (closed form for a plane and a sphere; conservative advancement on the 1-Lipschitz
// distance for a capped cylinder and a mesh, which returns a t at or before it).
double first_touch(const PlacedObstacle& obstacle, const Vec3& p, const Vec3& u);

// The normal impulse (kg*m/s) the band's damping gave a vertex against an obstacle in a
// step: what stopped its landing there (or, negative, held back its rebound), which the
// next step's lagged friction takes with the barrier's force (a landing's impact is the
// damping's, not the barrier's). An impact is an impulse: carried as a force, a landing
// in a short substep would weigh more in a longer step after it.
struct LandingImpulse {
  int vertex = -1;
  int obstacle = -1;  // index in Model::obstacles
  double impulse = 0.0;
};

// The barrier contacts of one implicit step, whose equation applies the forces with weight
// beta: M (v - v_base) = beta f + ... End positions are x_end(v) = x_end_base + beta_end v;
// the barrier acts on them like the other forces, so its impulse on the step equation is
// -beta grad B(x_end), its matrix beta beta_end Hess B and its share of the incremental
// potential (beta / beta_end) B. (Backward Euler and BDF-2: beta = beta_end. The midpoint
// rule solves for the midpoint velocity w with beta = h / 2 and ends at x_n + h w: its
// step v_{n+1} - v_n = 2 (w - v_n) then takes the impulse -h grad B(x_end).)
class BarrierContact {
 public:
  // At the start of a step from positions x_n at t (s) to t_end: the analytic obstacles
  // placed at t_end, and the lagged friction of every vertex within dhat of an obstacle
  // with friction at x_n (normal impulse beta |b'(d)|, plus the damping's impulse that
  // the last step's remember_landings kept), and of every self pair and mesh corner or edge
  // pair within dhat at x_n (the latter under the barrier only). With the constraints model
  // (model.implicit.contact) it takes only the cloth against itself, where the scene
  // declares self_collision, and a mesh obstacle's corners and edges past
  // feature_thickness (the cloth's vertices against the obstacles are then the solve's
  // constraints); with neither it clears itself and every call below does nothing.
  void begin(const Model& model, const Vec3List& x_n, const Vec3List& x_end_base,
             double beta, double beta_end, double t, double t_end);
  bool enabled() const { return enabled_; }
  // After a step's solve: keeps the damping's normal impulses at its end velocities (v the
  // step's unknown, m/s) for the next step's friction. A step taken again restores the
  // landings it started with.
  void remember_landings(const Vec3List& v);
  const std::vector<LandingImpulse>& landings() const { return landings_; }
  void restore_landings(const std::vector<LandingImpulse>& landings) { landings_ = landings; }
  bool takes_obstacles() const { return takes_obstacles_; }  // the barrier model

  double dhat() const { return dhat_; }

  // The initial guess, which must be feasible: moves the end position of each vertex whose
  // x_end(v) is closer than dhat / 2 to an obstacle out along the normal to the larger of
  // its gap at x_n and the gap where the barrier holds the impulse pressing it (from its
  // momentum against the surface, M (v_surface - v_base), and the forces f(x_n), N, that
  // forces() returns, called only if a vertex is that close, and then before any v is
  // changed, so the forces see the velocities v came in with), at most dhat / 2. A resting
  // vertex starts where it rests; one whose gap at x_n no load explains (a sheet laid on the
  // surface, at a gap of rounding) starts where the load is held (docs/implicit.md, "The
  // barrier's initial guess").
  // Against a mesh obstacle's corners and edges (mesh_barrier.h) the guess is then checked
  // on the paths from x_n, with the obstacle where it starts the step, to the guess, with
  // it where it ends, and drawn back to 0.9 of the first touch, toward x_n carried by that
  // obstacle's motion near it, at most four times (then pairs still crossed are left out
  // of the step). Self pairs are checked on the same paths and drawn back toward x_n.
  // Every draw-back is followed by the push out of the obstacles; self pairs whose paths
  // still touch after the last one are held apart (hold_touching_pairs).
  void make_feasible(Vec3List& v, const Vec3List& v_base,
                     const std::function<const Vec3List&()>& forces);

  // Takes the normal damping's normals and coefficients at x_end(v), each coefficient at
  // most kMaxStepDamping m / beta_end, and holds them until the next call (Newton calls it
  // at each accepted iterate, so a converged step meets the damping at its end positions;
  // within a line search the damping is linear in v).
  // The damping acts on the velocity the step ends with, v_end = v_n + a (v - v_n) with
  // a = beta_end / beta and v_n (m/s) the velocities at the start: v itself for backward
  // Euler and BDF-2, 2 w - v_n for the midpoint rule's w, whose damping is then
  // backward Euler's (L-stable: a stiff damper does not flip the velocity every step).
  void freeze_damping(const Vec3List& v, const Vec3List& v_n);

  // (beta / beta_end) times the barrier energy at x_end(v), the friction potential at v
  // and (beta / a) times the frozen damping's potential at v_end (J); +infinity where a
  // vertex is at or beyond d = 0.
  double potential(const Vec3List& v) const;
  // Adds -beta grad B(x_end(v)), the friction impulses F(v) and the frozen damping's
  // impulses beta f(v_end) to rhs (3V), kg*m/s.
  void add_impulses(const Vec3List& v, Eigen::VectorXd& rhs) const;
  // Adds beta beta_end Hess B (PSD part: a vertex's and a mesh pair's b'' n n^T, a self
  // pair's whole Hessian projected), -dF/dv and the damping's -beta a df/dv_end to the
  // system's blocks, kg. A self pair's friction acts on the weighted sum of its vertices'
  // motions through a symmetric positive semi-definite 3x3 block K: (w w^T) (x) K. A
  // pair's blocks between two vertices that share no triangle lie outside the system's
  // pattern and go to coupling(), which the solve adds to the matrix (by product in PCG,
  // into the preconditioner's factor).
  void add_hessian(const Vec3List& v, SystemMatrix& system);
  // The blocks of the last add_hessian outside the pattern; null when there are none.
  const OffPatternBlocks* coupling() const { return coupling_.empty() ? nullptr : &coupling_; }
  // The largest step length along dv (3V), at most 1, that keeps every vertex and every
  // mesh feature pair and self pair at d > 0: kBarrierStepFraction of the first touch. It
  // also finds the pairs the other calls take, those that may come within dhat on the way;
  // the calls must stay on that way (the line search does).
  double largest_step(const Vec3List& v, const Eigen::VectorXd& dv);

  // Vertices within dhat of an obstacle at x_end(v), mesh feature pairs and self pairs
  // within dhat, and the smallest gap, m; *pairs receives the pairs alone.
  int active(const Vec3List& v, double* smallest_gap = nullptr, int* pairs = nullptr) const;

  // The barrier energy of positions x at time t (s), J, of the vertices and pairs begin
  // takes: what the barrier adds to the total energy of a state (0 when it takes nothing).
  // Pairs the barrier cannot hold (not apart) count nothing.
  double energy_of(const Model& model, const Vec3List& x, double t);

 private:
  Vec3 end_position(const Vec3List& v, int i) const {
    return (*x_end_base_)[i] + beta_end_ * v[i];
  }
  Vec3 end_velocity(const Vec3List& v, int i) const {
    return (*v_start_)[i] + (beta_end_ / beta_) * (v[i] - (*v_start_)[i]);
  }
  // Calls visit(vertex, term) for each free vertex and obstacle within dhat at x_end(v).
  template <typename Visit>
  void for_each_term(const Vec3List& v, Visit visit) const;
  // Calls visit(gap, kappa) for each mesh feature pair and self pair at positions x.
  template <typename Visit>
  void for_each_pair(const Vec3List& x, Visit visit) const;
  bool has_pairs() const { return features_.active() || self_.active(); }
  // The end positions of all vertices at v, in x_end_ (when a mesh has features).
  const Vec3List& end_positions(const Vec3List& v) const;
  // After make_feasible's last push out: the vertices of self pairs whose paths from x_n
  // to the guess still touch are held at x_n (where those pairs are apart), where every
  // obstacle is clear of them, so that the solve keeps those pairs instead of leaving them
  // out of the step. paths_found: self_ already holds the pairs of those paths. Returns
  // whether self_ holds the pairs of the paths to the guess it leaves.
  bool hold_touching_pairs(Vec3List& v, bool paths_found);
  // Pushes the end position of each free vertex closer than dhat / 2 out (make_feasible);
  // f: the forces at x_n once taken.
  void push_out(Vec3List& v, const Vec3List& v_base,
                const std::function<const Vec3List&()>& forces, const Vec3List*& f) const;
  bool enabled_ = false;
  bool takes_obstacles_ = false;
  const Model* model_ = nullptr;
  const Vec3List* x_start_ = nullptr;  // x_n, m
  const Vec3List* x_end_base_ = nullptr;
  double beta_ = 0.0;      // s
  double beta_end_ = 0.0;  // s
  double dhat_ = 0.0;      // m
  double stiffness_dt_ = 0.0;  // s, of kappa
  std::vector<PlacedObstacle> placed_;  // at the end of the step
  std::vector<PlacedObstacle> placed_start_;  // the same obstacles at the start
  std::vector<double> kappa_;           // (V) barrier stiffness, kg/s^2
  struct Friction {
    int vertex = -1;
    SlidingFriction law;
  };
  std::vector<Friction> friction_;
  // Friction between the two pieces of a self pair within dhat at x_n, on the relative
  // velocity of its closest points, sum_k w_k v_k, with the weights and normal of x_n.
  struct PairFriction {
    PairGap pair;
    SlidingFriction law;
    Vec3 relative(const Vec3List& v) const;  // m/s
  };
  std::vector<PairFriction> pair_friction_;
  // Adds (w w^T) (x) K of a self pair to the system, or to coupling_ where the system has
  // no block.
  void add_pair_blocks(const PairGap& pair, const Mat3& block, SystemMatrix& system);
  // The same for a pair's Hessian over its vertices (pair_gap.h), but its pinned vertices'.
  void add_pair_hessian(const PairGap& pair, const PairMatrix& hessian, SystemMatrix& system);
  struct Damping {
    int vertex = -1;
    int obstacle = -1;
    NormalDamping law;
  };
  std::vector<Damping> damping_;  // frozen by freeze_damping
  std::vector<LandingImpulse> landings_;  // of the last step, by remember_landings
  std::vector<double> landing_scratch_;  // (V) one obstacle's landing impulses, kg*m/s
  const Vec3List* v_start_ = nullptr;  // v_n, m/s
  MeshFeatureBarrier features_;         // mesh corners and edges against the cloth
  MeshFeatureBarrier energy_features_;  // the same for energy_of
  SelfBarrier self_;                    // the cloth against itself
  SelfBarrier energy_self_;             // the same for energy_of
  OffPatternBlocks coupling_;
  mutable Vec3List x_end_, x_path_;     // m
};

// kappa = m / dt^2 (kg/s^2) of a vertex of mass m (kg) for dt (s): the scene's step, or
// model.implicit.barrier_stiffness_dt if set (the same barrier at every step).
double barrier_stiffness(double mass, double dt);

// The gap at which the barrier pushes with the given force (N), m: -b'(d) = force for
// kappa (kg/s^2) and dhat (m); dhat where the force is not positive.
double holding_gap(double force, double dhat, double kappa);

// Cloth laid by the scene closer to an obstacle than the gap where the barrier holds it (on
// its thickness, say) would be thrown off by the first step: the solve moves it out to that
// gap and the step's end velocity keeps the motion. At a run's start, before its first
// step, each free vertex within dhat of an obstacle (placed at t, s) is moved out along the
// normal, positions only, to the gap where the barrier holds the force f (N) pressing it
// there, dhat where nothing presses it; a vertex already beyond that gap stays. This is
// the paper's position correction: positions move, velocities do not. Returns how many
// vertices moved.
int lift_to_holding_gaps(const Model& model, Vec3List& x, const Vec3List& f, double t);

// Layers of cloth laid by the scene within dhat of each other (where the self barrier
// pushes, with many pairs on each vertex of a flat contact) are thrown apart by the first
// step as cloth on an obstacle was: two sheets laid 1 mm beyond the thickness flew up at
// 2.7 m/s. At a run's start, before its first step (and again after lift_to_holding_gaps
// if that moved any vertex), the self pairs found apart but closer than dhat are opened
// toward dhat, positions only: each asks the piece farther from the obstacles (a layer on
// the ground stays, the one on it rises) to move as a whole along its normal by what opens
// it to dhat, or both pieces, shared by mass, where they are as far; a piece with a pinned
// vertex stays. Each vertex takes the largest move asked of it, and all moves stop at
// kBarrierStepFraction of the first touch of the cloth with itself or an obstacle on their
// paths. Rounds of this over the pairs found again, until none is closer than dhat (or
// kSeparationRounds). Pairs not apart (closer than the thickness) are left to the solve and
// the collision stage. Returns how many pair openings were asked.
int separate_laid_layers(const Model& model, Vec3List& x, double t);

// BarrierContact::energy_of without a contact object at hand (its mesh features found
// again on each call).
double barrier_energy_of(const Model& model, const Vec3List& x, double t);

// dhat of a model, m: model.implicit.barrier_distance if set (scene key
// implicit.barrier_distance), else kBarrierEdgeFraction of the mean rest edge length.
double barrier_distance(const Model& model);

}  // namespace tissu
