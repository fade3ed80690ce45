// A mesh obstacle's own corners and convex edges against the cloth's triangles and edges,
// in the barrier model (barrier_contact.h), so that a table's edge or a box's corner cannot
// cut through a cloth triangle between its vertices while the vertices keep their gaps to
// the surface. IPC's point-triangle and edge-edge barriers (Li et al. 2020) with a rigid
// obstacle placed where the step ends:
//   gap = distance between the feature and the cloth primitive - the obstacle's thickness (m)
// under the vertex barrier's b(d), dhat and kappa (the mean of the primitive's free
// vertices'). By the closest points, d gap / d x_i = w_i n, with w_i the weight of cloth
// vertex i in the closest point and n the unit direction from the feature to it; the
// Hessian is the Gauss-Newton part b'' (w w^T) (x) n n^T, positive semi-definite (the
// whole Hessian, as the self pairs take it, cost more Newton iterations on the rising box;
// docs/implicit.md, "The self pairs' whole Hessian").
// Only convex features take part: a flat or concave edge, and a vertex with no convex edge,
// cannot pierce a cloth triangle whose vertices are outside the solid. Convex edges bent by
// less than 2 T / L (thickness T, the cloth's longest rest edge L) take no part either, nor
// do corners all of whose edges are that gentle: one such edge cannot bring a cloth edge
// whose ends keep the thickness through the surface. Several in a row can (a curved part
// sags by about L^2 / 8R under a cloth edge, R its radius); there only the vertices' gaps
// and the collision stage after the solve keep the cloth out.
// The cloth's vertices against the mesh's surface are BarrierContact's vertex gaps, or under
// the constraints model (model.implicit.contact) the solve's constraints, which hold them at
// T: the pairs then take a thinner layer (feature_thickness). Under the barrier the pairs
// also take the obstacle's friction (BarrierContact::begin, for_each_contact_at_start):
// where cloth turns over an edge they carry the turn's normal force.
// Tested in tests/physics/mesh_barrier_test.cpp.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "collision/bvh.h"
#include "core/types.h"
#include "physics/model.h"
#include "physics/obstacle.h"
#include "physics/pair_gap.h"

namespace tissu {

class ClosedSurface;

// The thickness (m) past which a mesh obstacle's corners and edges meet the cloth in an
// implicit step: the obstacle's own T under the barrier model, T / 2 under the constraints.
// These hold the cloth's vertices at T exactly, so a sheet lying flat across a box's edge
// is at T from it, and a cloth edge between two vertices held at T around a convex edge
// passes closer than T (a chord of the rounded layer): a barrier past T would hold such
// edges where they are, and a sheet could not slide over the edge.
double feature_thickness(const Model& model, const Obstacle& obstacle);

class MeshFeatureBarrier {
 public:
  MeshFeatureBarrier();
  ~MeshFeatureBarrier();

  // The model's mesh obstacles placed at the step's start t and end t_end (s); their convex
  // features are found once per surface. Clears the pairs. The pairs' gaps are taken with
  // the obstacles at t_end, past feature_thickness.
  void begin(const Model& model, double t, double t_end);
  // Whether the model has a mesh obstacle.
  bool active() const { return !placed_.empty(); }

  // Finds the pairs that may come within dhat (m) on the straight paths of the cloth's
  // vertices from `from` to `to` (m), in each obstacle's own frame: `from` taken with the
  // obstacles where they end the step, or (from_start) where they start it. A pair whose
  // gap at `from` is not positive (the cloth already closer than the thickness, as the
  // collision stage may leave it) is left out: the barrier cannot hold what it does not
  // start apart.
  void find_pairs(const Vec3List& from, const Vec3List& to, double dhat, bool from_start = false);
  int num_pairs() const { return static_cast<int>(pairs_.size()); }
  int left_out() const { return left_out_; }

  // visit(gap) for each pair at positions x (m); pairs with every cloth vertex pinned
  // are not visited.
  template <typename Visit>
  void for_each_gap(const Vec3List& x, Visit visit) const {
    for (const Pair& p : pairs_) visit(gap_of(p, x));
  }

  // visit(gap, obstacle, surface_velocity) for each pair at positions x (m) with the
  // obstacles where they start the step (time t, s): `obstacle` indexes model.obstacles,
  // `surface_velocity` is the obstacle's rigid velocity (m/s) at the cloth's closest point.
  void for_each_contact_at_start(
      const Vec3List& x, double t,
      const std::function<void(const PairGap&, int, const Vec3&)>& visit) const;

  // The first fraction t in [0, 1] of the paths x + t u (m) at which a pair's gap falls to
  // zero, found by conservative advancement (at or before the touch); 1 if none does.
  double first_touch(const Vec3List& x, const Vec3List& u) const;
  // The same on the paths from x_n, where the obstacles start the step, to x_end, where they
  // end it, straight in each obstacle's frame; *mesh receives the index (into the model's
  // mesh obstacles that have features) of the first pair's obstacle.
  double first_touch_over_step(const Vec3List& x_n, const Vec3List& x_end, int* mesh) const;
  // Where p (m) ends the step when carried rigidly by that obstacle's motion, if p starts
  // the step within the obstacle's thickness plus `reach` plus that motion of its surface
  // (m); p itself farther away.
  Vec3 carried(int mesh, const Vec3& p, double reach) const;

 private:
  struct Features;
  struct Placed {
    const Features* features = nullptr;
    Vec3 rest_center = Vec3::Zero();  // the centre at t = 0, m
    Vec3 center = Vec3::Zero();       // at t_end, m
    Mat3 rotation = Mat3::Identity();
    Vec3 start_center = Vec3::Zero();  // at t, m
    Mat3 start_rotation = Mat3::Identity();
    double thickness = 0.0;  // m, feature_thickness
    int obstacle = -1;       // index into model.obstacles
    // p (world, m) in the surface's frame with the obstacle at t_end, or at t.
    Vec3 local(const Vec3& p) const { return rest_center + rotation.transpose() * (p - center); }
    Vec3 local_at_start(const Vec3& p) const {
      return rest_center + start_rotation.transpose() * (p - start_center);
    }
  };
  struct Pair {
    int mesh = 0;        // index into placed_
    int feature = 0;     // the surface's vertex id, or its edge id (edge_edge)
    int cloth = 0;       // cloth triangle id, or cloth edge id (edge_edge)
    bool edge_edge = false;
  };
  const Features& features_of(const std::shared_ptr<const ClosedSurface>& surface,
                              double least_angle);
  PairGap gap_of(const Pair& pair, const Vec3List& x) const;
  // The pair's gap with cloth vertex i at local(i), in the surface's frame (m); its normal
  // in world axes with the obstacle turned as it ends the step, or (at_start) starts it.
  template <typename Local>
  PairGap gap_at(const Pair& pair, Local local, bool at_start = false) const;
  // Conservative advancement of one pair along straight paths in the surface's frame,
  // from start(i) to end(i), up to `limit`.
  template <typename Start, typename End>
  double touch_along(const Pair& pair, Start start, End end, double limit) const;

  const Model* model_ = nullptr;
  std::vector<std::unique_ptr<Features>> cache_;
  std::vector<std::array<int, 2>> cloth_edges_;  // the cloth's edges, vertex ids
  double longest_edge_ = 0.0;                    // the cloth's longest rest edge, m
  uint64_t cloth_edges_mesh_ = 0;                // the model mesh_id they are of
  std::vector<Placed> placed_;
  std::vector<Pair> pairs_;
  int left_out_ = 0;
};

}  // namespace tissu
