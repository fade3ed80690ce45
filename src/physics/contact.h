// Contact of cloth vertices with obstacles inside an implicit step (docs/implicit.md).
//
// Normal direction: a hard constraint that the conjugate gradients keep exactly (the
// constrained direction is filtered out of the solve: Baraff & Witkin 1998; the
// prefiltered PCG of Tamstorf, Jones & McCormick 2015). With x_end(v) = x_end_base +
// beta_end v the vertex's position at the end of the step, n . x_end stays at the tangent
// plane of the obstacle at its closest point, moved out by the obstacle's thickness:
// n . v = target. The tangent plane lies outside a convex obstacle (sphere, cylinder,
// plane), so a vertex kept on it never ends inside. The solve measures the normal impulse
// J_n each contact applies. During a step contacts are only added (where the iterate
// would put a vertex inside an obstacle), so the contact set cannot cycle; a contact that
// pulls at the end of the step (J_n below minus a tenth of its vertex's weight impulse) is
// released for the next step.
//
// Tangential direction: Coulomb friction from the normal impulse, inside the solve, with
// each contact's mode chosen from the end of the step before:
// - stick: the tangential velocity equals the surface's (three constrained directions);
//   the solve measures the tangential impulse J_t this needs;
// - slide: a friction impulse of at most mu J_n acts against the sliding velocity u,
//   F(u) = -mu J_n f1(|u|) u / |u| with f1(y) = 2 y / eps - y^2 / eps^2 below eps and 1
//   above (eps = kSlidingSpeed, the smoothed Coulomb friction of IPC, Li et al. 2020),
//   with the normal force of the end of the step before (J_n / beta) held fixed in the
//   step and turned into an impulse over this step's beta. F is a function of the
//   unknown velocity, with its Jacobian in the system, so a contact that friction slows
//   down stops smoothly instead of having its friction reverse it.
// After each whole Newton step that changed no contact, a sticking contact whose |J_t|
// exceeds mu J_n slides and the solve goes on (once per contact and step); before the
// solve has converged, only one that pushes (J_n > 0). A sliding contact that ends a step
// slower than eps and no faster than the step before sticks in the next (its smoothed
// friction, below mu J_n, holds its load), unless a stick let it go in this step. After
// the k-th let-go in a row it slides 2^(k-1) - 1 more steps first, at most
// kSlideStepsAfterLetGo: cloth creeping over a cylinder had its sticks let go and tried
// again every other step, each time over 15-30 Newton iterations. A new
// contact on an obstacle with friction starts in the mode Coulomb's law predicts from the
// velocity it was caught with (sticking when no velocity is given).
//
// A vertex in a corner of two obstacles (a floor and a wall) holds a contact on each, both
// sliding, kept together: its velocity is constrained along both normals (which must be
// more than kCornerCosine apart), and the reaction is split between them. With one contact,
// the second obstacle met the vertex only after the solve, and the collision stage's
// corrections of it gained energy.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "core/types.h"
#include "physics/model.h"
#include "physics/obstacle.h"

namespace tissu {

class SystemMatrix;

enum class ContactMode : uint8_t { Stick, Slide };

// What a vertex's contacts constrain: nothing, the normal (sliding), all three directions
// (sticking), or two normals (a corner).
enum class ConstrainedDirections : uint8_t { None, Normal, All, TwoNormals };

// Sliding speed below which the friction of a sliding contact falls smoothly to zero, m/s.
constexpr double kSlidingSpeed = 1e-3;
// The most steps a contact that sticks let go again and again slides on before a slow
// slide sticks it again (the wait doubles with each let-go in a row: 0, 1, 3, 7, 8).
constexpr int kSlideStepsAfterLetGo = 8;
// A vertex takes a second contact only where the two normals' cosine is below this (about
// 8 degrees apart): nearly parallel constraints are nearly one.
constexpr double kCornerCosine = 0.99;

// Smoothed Coulomb friction of one sliding contact (IPC's lagged friction, Li et al. 2020):
// F(v) = -limit f1(|u|) u / |u| on the sliding velocity u (v relative to the surface,
// tangential), f1(y) = 2 y / eps - y^2 / eps^2 below eps = kSlidingSpeed, 1 above.
struct SlidingFriction {
  Vec3 normal = Vec3::UnitZ();           // unit normal of the surface
  Vec3 surface_velocity = Vec3::Zero();  // m/s
  double limit = 0.0;                    // mu J_n, kg*m/s

  Vec3 sliding(const Vec3& v) const;    // u, m/s
  Vec3 impulse(const Vec3& v) const;    // F(v), kg*m/s
  double potential(const Vec3& v) const;  // limit f0(|u|) with f0' = f1, kg*m^2/s^2
  Mat3 jacobian(const Vec3& v) const;   // -dF/dv, kg (symmetric positive semi-definite)
};

struct VertexContact {
  int vertex = -1;
  int obstacle = -1;                     // index in Model::obstacles
  Vec3 normal = Vec3::UnitZ();           // outward unit normal of the tangent plane
  double offset = 0.0;                   // the plane: normal . x_end >= offset, m
  Vec3 surface_velocity = Vec3::Zero();  // m/s
  double friction = 0.0;                 // Coulomb coefficient
  double target = 0.0;                   // normal velocity that lands on the plane, m/s
  ContactMode mode = ContactMode::Slide;
  bool switched = false;                 // switched to sliding during this step
  double normal_impulse = 0.0;           // J_n of the last solve (0 if it pulls), kg*m/s
  double pull = 0.0;                     // -J_n of the last solve if it pulls, kg*m/s
  Vec3 tangential_impulse = Vec3::Zero();  // J_t of the last solve while sticking, kg*m/s
  // mu J_n while sliding; a stick caught in this step: what it holds (switch_modes), kg*m/s
  double friction_limit = 0.0;
  // The impulse a new contact needs to stop the approach it was caught with (on the step's
  // unknown), less what its normal impulses have absorbed so far, kg*m/s: sliding, or a
  // stick let go, its first step's friction took mu times it whole, so the next steps'
  // friction leaves it out of J_n.
  double unabsorbed_impact = 0.0;
};

// The sliding friction of contact c: its normal, surface velocity and friction limit.
SlidingFriction friction_of(const VertexContact& c);

// The vector a n_a + b n_b whose components along the unit normals n_a and n_b (not
// parallel) are r_a and r_b: the change that meets both rows of a vertex's two contacts.
Vec3 along_two_normals(const Vec3& n_a, const Vec3& n_b, double r_a, double r_b);

// The contacts of one step.
class ContactSet {
 public:
  void clear(int num_vertices);
  bool empty() const { return contacts_.empty(); }
  int size() const { return static_cast<int>(contacts_.size()); }
  const std::vector<VertexContact>& contacts() const { return contacts_; }
  int contact_of(int vertex) const { return of_vertex_[vertex]; }
  // A vertex's second contact, in a corner of two obstacles, or -1.
  int second_contact_of(int vertex) const { return second_of_vertex_[vertex]; }
  ConstrainedDirections constrained_at(int vertex) const;

  // Adds a contact for each free vertex without one whose end position x_end lies closer
  // to an obstacle than its thickness plus `margin` (m), at the obstacle's closest point;
  // for a vertex in contact at the end of the last step, plus the larger of `margin` and
  // `remembered_margin` (m); for one released then, only once inside. A new contact with
  // friction starts sticking, or, given the velocities (m/s) and the step's beta (s), in
  // the mode Coulomb's law predicts from them. Then, by the same rules, a second contact
  // on another obstacle for each vertex with one (both then slide, the friction of a
  // sticking one from the impulse its approach needed). `share`: the part of a change of
  // the end velocity that the step's unknown takes (1; 1/2 for the midpoint rule, whose
  // end velocity 2 w - v_n doubles its unknown's impulses). Returns how many were added.
  int detect(const Model& model, const std::vector<PlacedObstacle>& placed,
             const Vec3List& x_end, double margin, double remembered_margin = 0.0,
             const Vec3List* velocities = nullptr, double beta = 0.0, double share = 1.0);

  // The normal velocity of every contact that puts x_end on its plane:
  // (offset - n . x_end_base) / beta_end.
  void set_targets(const Vec3List& x_end_base, double beta_end);

  // Sets the constrained components of v to their required values.
  void project(Vec3List& v) const;

  // Zeroes the constrained components of y (3V), the filter S of the solve.
  void filter(Eigen::VectorXd& y) const;

  // Removes from each contact's vertex velocity (m/s) its approach to the contact's surface
  // (the normal part of the velocity relative to the surface, where negative); a vertex
  // in a corner ends approaching neither surface.
  void stop_approach(Vec3List& v) const;

  // Adds the sliding contacts' friction impulses F(v) to rhs (3V), kg*m/s.
  void add_friction(const Vec3List& v, Eigen::VectorXd& rhs) const;

  // The friction's dissipation potential at v, sum mu J_n f0(|u|) with f0' = f1, whose
  // gradient is -F(v) (kg*m^2/s^2): the line search's merit holds it.
  double friction_potential(const Vec3List& v) const;

  // Adds -dF/dv (kg, symmetric positive semi-definite) to the system's diagonal blocks.
  void add_friction_jacobian(const Vec3List& v, SystemMatrix& system) const;

  // After a solve: `reaction` (3V) holds A dv - rhs, the constraint impulses at the
  // constrained vertices. Records them (a pulling J_n as 0 for friction).
  void update(const Eigen::VectorXd& reaction);

  // After a whole Newton step on these contacts (so that the impulses judged are that
  // solve's): sticking contacts whose solve needed more tangential impulse than mu J_n
  // slide; before the solve has `converged`, only those that push (J_n > 0: one not yet
  // loaded would slide without friction). A contact switches at most once in a step.
  // Returns how many switched.
  int switch_modes(bool converged);

  // At the end of a step with velocities v whose impulses act over beta (s): releases for
  // the next step the contacts that pulled harder than `release` (per vertex, kg*m/s),
  // chooses the others' modes (see above) and remembers them with their friction forces,
  // mu J_n / beta, which the next step turns into impulses over its own beta (BDF-2's
  // first step is backward Euler's, over h; the next ones are over 2 h / 3).
  void remember(const Vec3List& v, const std::vector<double>& release, double beta);
  // After remember: the step then stops the normal part of a held contact's end velocity v
  // (m/s) outside the solve (BDF-2, the midpoint rule: stop_held_contacts). An approach
  // stopped absorbs what is left of the contact's impact. With `whole` the impulse counts
  // as its J_n would: the rest of an approach adds to its next friction, a rebound taken
  // back takes from it (beta: the step's, s; share as for detect). The midpoint rule needs
  // that: its end velocity 2 w - v_n reflects a landing, whose J_n on w held the
  // reflection too. Without `whole` (BDF-2) only a rebound of a contact caught with an
  // impact is taken from the next friction: a catch's base can lie beyond the surface.
  void settle_stopped_normal(const Model& model, const Vec3List& v, double beta, double share,
                             bool whole);

  int stuck() const;  // contacts sticking

 private:
  std::vector<VertexContact> contacts_;
  std::vector<int> of_vertex_;         // (V) index into contacts_, or -1
  std::vector<int> second_of_vertex_;  // (V) the second contact's index, or -1
  // (V) what each vertex's contact will do if it is in contact at the next step.
  struct Memory {
    bool in_contact = false;
    bool released = false;  // pulled at the end of the last step: not caught unless inside
    ContactMode mode = ContactMode::Stick;
    double friction_force = 0.0;  // mu J_n / beta while sliding, N
    double unabsorbed_impact = 0.0;  // kg*m/s, VertexContact::unabsorbed_impact
    double sliding_speed = INFINITY;  // m/s at the end of the step, while sliding
    int obstacle = -1;                // the second contact's obstacle
    int slide_steps_left = 0;         // before a slow slide sticks it again
    int let_go = 0;                   // sticks let go in a row
  };
  std::vector<Memory> memory_;
  std::vector<Memory> second_memory_;  // (V) of the second contacts, for their obstacle
  // Adds the contact of vertex i on obstacle o (placed) at its closest point p, in the mode
  // its memory `last` or Coulomb's law gives.
  void add_contact(const Model& model, const PlacedObstacle& placed, int o, int i,
                   const SurfacePoint& p, const Vec3List& x_end, const Memory& last,
                   const Vec3List* velocities, double beta, double share);
  // (V) the memories remember replaced, which it reads; then its scratch.
  std::vector<Memory> last_memory_, last_second_memory_;
  // Calls visit(c, second) once for each vertex in contact: its (first) contact c and its
  // second contact, or null.
  template <typename Visit>
  void for_each_vertex(Visit visit) const;
};

}  // namespace tissu
