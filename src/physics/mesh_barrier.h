// A mesh obstacle's own corners and convex edges against the cloth's triangles and edges,
// in the barrier model (barrier_contact.h), so that a table's edge or a box's corner cannot
// cut through a cloth triangle between its vertices while the vertices keep their gaps to
// the surface. IPC's point-triangle and edge-edge barriers (Li et al. 2020) with a rigid
// obstacle placed where the step ends:
//   gap = distance between the feature and the cloth primitive - the obstacle's thickness (m)
// under the vertex barrier's b(d), dhat and kappa (the mean of the primitive's free
// vertices'). By the closest points, d gap / d x_i = w_i n, with w_i the weight of cloth
// vertex i in the closest point and n the unit direction from the feature to it; the
// Hessian is the Gauss-Newton part b'' (w w^T) (x) n n^T, positive semi-definite.
// Only convex features take part: a flat or concave edge, and a vertex with no convex edge,
// cannot pierce a cloth triangle whose vertices are outside the solid.
// The cloth's vertices against the mesh's surface are BarrierContact's vertex gaps.
// Tested in tests/physics/mesh_barrier_test.cpp.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "collision/bvh.h"
#include "core/types.h"
#include "physics/model.h"
#include "physics/obstacle.h"

namespace tissu {

class ClosedSurface;

// One pair's gap at given cloth positions: the cloth vertices it moves, their weights in
// the closest point, and the unit normal from the feature toward the cloth (world).
struct PairGap {
  double d = 0.0;  // m, past the thickness
  Vec3 normal = Vec3::UnitZ();
  int vertices[3] = {-1, -1, -1};
  double weights[3] = {0.0, 0.0, 0.0};
  int count = 0;  // 3 for a cloth triangle, 2 for a cloth edge
};

class MeshFeatureBarrier {
 public:
  MeshFeatureBarrier();
  ~MeshFeatureBarrier();

  // The model's mesh obstacles placed at t_end (s); their convex features are found once
  // per surface. Clears the pairs.
  void begin(const Model& model, double t_end);
  // Whether the model has a mesh obstacle.
  bool active() const { return !placed_.empty(); }

  // Finds the pairs that may come within dhat (m) on the straight paths of the cloth's
  // vertices from `from` to `to` (m). A pair whose gap at `from` is not positive (the cloth
  // already closer than the thickness, as the collision stage may leave it) is left out:
  // the barrier cannot hold what it does not start apart.
  void find_pairs(const Vec3List& from, const Vec3List& to, double dhat);
  int num_pairs() const { return static_cast<int>(pairs_.size()); }
  int left_out() const { return left_out_; }

  // visit(gap) for each pair at positions x (m); pairs with every cloth vertex pinned
  // are not visited.
  template <typename Visit>
  void for_each_gap(const Vec3List& x, Visit visit) const {
    for (const Pair& p : pairs_) visit(gap_of(p, x));
  }

  // The first fraction t in [0, 1] of the paths x + t u (m) at which a pair's gap falls to
  // zero, found by conservative advancement (at or before the touch); 1 if none does.
  double first_touch(const Vec3List& x, const Vec3List& u) const;

 private:
  struct Features;
  struct Placed {
    const Features* features = nullptr;
    Vec3 rest_center = Vec3::Zero();  // the centre at t = 0, m
    Vec3 center = Vec3::Zero();       // at t_end, m
    Mat3 rotation = Mat3::Identity();
    double thickness = 0.0;  // m
  };
  struct Pair {
    int mesh = 0;        // index into placed_
    int feature = 0;     // the surface's vertex id, or its edge id (edge_edge)
    int cloth = 0;       // cloth triangle id, or cloth edge id (edge_edge)
    bool edge_edge = false;
  };
  const Features& features_of(const ClosedSurface& surface);
  PairGap gap_of(const Pair& pair, const Vec3List& x) const;
  // The pair's gap with cloth vertex i at position(i) (m).
  template <typename Position>
  PairGap gap_at(const Pair& pair, Position position) const;

  const Model* model_ = nullptr;
  std::vector<std::unique_ptr<Features>> cache_;
  std::vector<std::array<int, 2>> cloth_edges_;  // the cloth's edges, vertex ids
  uint64_t cloth_edges_mesh_ = 0;
  std::vector<Placed> placed_;
  std::vector<Pair> pairs_;
  int left_out_ = 0;
};

}  // namespace tissu
