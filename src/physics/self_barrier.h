// Cloth against itself in the barrier model (barrier_contact.h), for scenes that declare
// self_collision: IPC's point-triangle and edge-edge barriers (Li et al. 2020) between
// pieces of the cloth that share no vertex,
//   gap = distance between a vertex and a triangle, or two edges - the self-collision
//         thickness T (m),
// under the vertex barrier's b(d), dhat and kappa (the mean of the pair's free vertices'),
// an edge-edge pair's barrier times IPC's mollifier where its edges lie nearly parallel
// (edge_mollifier, pair_gap.h).
// By the closest points, d gap / d x_k = w_k n (PairGap), n the unit direction from the
// second piece to the first; the Hessian is b'' grad grad^T + b' Hess gap (pair_gap.h),
// projected to positive semi-definite, as in IPC. Its blocks between the two pieces lie
// outside the step's matrix pattern: BarrierContact hands them to the solve apart
// (OffPatternBlocks).
// Left out:
//   - pairs closer than T + dhat in the rest shape (neighbours in the fabric, which the
//     barrier would push apart while the cloth lies flat);
//   - pairs not apart at the start of their path (closer than T, as the collision stage
//     may leave them): the barrier cannot hold what it does not start apart.
// Pairs are found along the straight paths of the vertices (those whose gap may fall
// below dhat on the way), and the first touch on those paths by additive conservative
// advancement (the gap falls no faster than the pair's spread of motion about its mean),
// so the line search never lets a pair reach d = 0.
// Tested in tests/physics/self_barrier_test.cpp.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "collision/bvh.h"
#include "core/types.h"
#include "physics/mesh_barrier.h"
#include "physics/model.h"

namespace tissu {

class SelfBarrier {
 public:
  // For the model's cloth; inactive without self_collision. Clears the pairs.
  void begin(const Model& model);
  bool active() const { return model_ != nullptr; }

  // Finds the pairs that may come within dhat (m) on the straight paths of the cloth's
  // vertices from `from` to `to` (m).
  void find_pairs(const Vec3List& from, const Vec3List& to, double dhat);
  int num_pairs() const { return static_cast<int>(pairs_.size()); }
  int left_out() const { return left_out_; }

  // visit(gap) for each pair at positions x (m).
  template <typename Visit>
  void for_each_gap(const Vec3List& x, Visit visit) const {
    for (const Pair& p : pairs_) visit(gap_of(p, x));
  }
  // The gap of vertex ids[0] to triangle ids[1..3], or (edge_edge) of edge ids[0..1] to
  // edge ids[2..3], at positions x (m).
  PairGap gap_of_vertices(const std::array<int, 4>& ids, bool edge_edge, const Vec3List& x) const;

  // The first fraction t in [0, 1] of the paths from `from` to `to` (m) at which a pair's
  // gap falls to zero, at or before the touch; 1 if none does.
  double first_touch(const Vec3List& from, const Vec3List& to) const;

  // The vertices of the pairs whose paths from `from` to `to` (m) touch, as first_touch
  // finds a touch.
  std::vector<std::array<int, 4>> touching_pairs(const Vec3List& from, const Vec3List& to) const;

 private:
  struct Pair {
    std::array<int, 4> v;  // vertex, triangle; or edge, edge
    bool edge_edge = false;
  };
  PairGap gap_of(const Pair& pair, const Vec3List& x) const {
    return gap_of_vertices(pair.v, pair.edge_edge, x);
  }
  // The same with vertex k at position(k).
  template <typename Position>
  PairGap gap_at(const std::array<int, 4>& ids, bool edge_edge, Position position) const;
  bool neighbours_at_rest(const Pair& pair, double reach) const;
  // The first touch of one pair on its paths, at most `before`.
  double touch_of(const Pair& pair, const Vec3List& from, const Vec3List& to,
                  double before) const;
  // How far the pair's gap may fall on the paths from `from` to `to`, m: the largest motion
  // about the four vertices' mean motion on one side plus that on the other.
  static double closing_bound(const Pair& pair, const Vec3List& from, const Vec3List& to);

  const Model* model_ = nullptr;
  double thickness_ = 0.0;  // m
  std::vector<std::array<int, 2>> edges_;  // the cloth's edges, vertex ids
  uint64_t edges_mesh_ = 0;                // the model mesh_id they are of
  Bvh triangle_tree_, edge_tree_;
  int calls_since_build_ = 0;  // of find_pairs, modulo kCallsPerBuild
  std::vector<Box3> boxes_;
  std::vector<Pair> pairs_;
  int left_out_ = 0;
};

}  // namespace tissu
