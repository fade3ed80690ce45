// Bounding-volume hierarchy of axis-aligned boxes: a binary tree over primitives (given
// only by their boxes), built top-down by the surface area heuristic (binned). Each inner node holds both children's boxes in single precision, rounded
// outward (one cache line per node visited); leaves test the primitives' own boxes in
// double precision, so every query answers exactly as brute force over the boxes would.
// Box tests at the leaves are without branches (their outcomes are hard to predict) and
// give their hits in leaf order: the order of the pairs found is that of plain loops.
// Queries: primitives overlapping a box, overlapping pairs within one tree or between two,
// and the primitive nearest to a point. refit() moves the boxes of the same primitives
// without rebuilding (deforming cloth). Tested in tests/collision/bvh_test.
#pragma once

#include <Eigen/Geometry>
#include <cmath>
#include <utility>
#include <vector>

#include "core/types.h"

namespace tissu {

using Box3 = Eigen::AlignedBox3d;

class Bvh {
 public:
  // Builds the tree over primitives 0 .. boxes.size()-1, at most `leaf_size` (1..7) per
  // leaf: 2 suits nearest-point queries, more suits overlap queries of many boxes.
  void build(const std::vector<Box3>& boxes, int leaf_size = 2);
  // New boxes for the same primitives; the tree keeps its shape.
  void refit(const std::vector<Box3>& boxes);

  int num_primitives() const { return static_cast<int>(order_.size()); }
  bool empty() const { return order_.empty(); }
  const Box3& bounds() const { return bounds_; }
  const Box3& box_of(int primitive) const { return leaf_boxes_[slot_[primitive]]; }

  // visit(primitive) for every primitive whose box overlaps `query`.
  template <class Visit>
  void for_each_overlap(const Box3& query, Visit&& visit) const;

  // visit(i, j) once for every pair of distinct primitives with overlapping boxes.
  template <class Visit>
  void for_each_self_overlap(Visit&& visit) const;

  // visit(i, j) for every primitive i of this tree and j of `other` with overlapping boxes.
  template <class Visit>
  void for_each_overlap_with(const Bvh& other, Visit&& visit) const;

  // The primitive nearest to p: `distance2(primitive, p)` returns the squared distance to
  // a primitive (m^2). Only primitives closer than sqrt(max_distance2) are considered (a
  // known upper bound, such as the distance to a primitive found before, prunes the
  // search). Returns -1 when there is none; *best_distance2 receives the nearest squared
  // distance (max_distance2 when none).
  template <class Distance2>
  int nearest(const Vec3& p, double max_distance2, Distance2&& distance2,
              double* best_distance2) const;

 private:
  friend class WideBvh;
  // A child reference: >= 0 an inner node; < 0 a leaf, ~(first * 8 + count) with `count`
  // primitives at order_[first ...].
  struct Node {
    float lo[2][3];  // children's boxes, rounded outward, m
    float hi[2][3];
    int child[2];
  };
  // A box in single precision (node boxes).
  struct FloatBox {
    float lo[3], hi[3];
    static FloatBox of(const Node& n, int k) {
      return {{n.lo[k][0], n.lo[k][1], n.lo[k][2]}, {n.hi[k][0], n.hi[k][1], n.hi[k][2]}};
    }
    bool overlaps(const FloatBox& o) const {
      return (lo[0] <= o.hi[0]) & (o.lo[0] <= hi[0]) & (lo[1] <= o.hi[1]) & (o.lo[1] <= hi[1]) &
             (lo[2] <= o.hi[2]) & (o.lo[2] <= hi[2]);
    }
    // Whether the exact box b meets this one (which holds every box it was rounded from).
    bool meets(const Box3& b) const {
      return (lo[0] <= b.max()[0]) & (b.min()[0] <= hi[0]) & (lo[1] <= b.max()[1]) &
             (b.min()[1] <= hi[1]) & (lo[2] <= b.max()[2]) & (b.min()[2] <= hi[2]);
    }
    float extent() const { return (hi[0] - lo[0]) + (hi[1] - lo[1]) + (hi[2] - lo[2]); }
  };
  FloatBox subtree_box(int ref) const;  // the root's (ref == root_) or a leaf's, rounded outward
  // Box3::intersects without branches.
  static bool meet(const Box3& a, const Box3& b) {
    return (a.min()[0] <= b.max()[0]) & (b.min()[0] <= a.max()[0]) & (a.min()[1] <= b.max()[1]) &
           (b.min()[1] <= a.max()[1]) & (a.min()[2] <= b.max()[2]) & (b.min()[2] <= a.max()[2]);
  }
  static bool is_leaf(int ref) { return ref < 0; }
  static int leaf_first(int ref) { return (~ref) >> 3; }
  static int leaf_count(int ref) { return (~ref) & 7; }
  // The nearest-query step at leaf `ref` (Bvh and WideBvh): a primitive of the leaf (ids in
  // `order`) nearer to p than best_d2 becomes `best`, its squared distance best_d2.
  template <class Distance2>
  static void nearest_in_leaf(const std::vector<int>& order, int ref, const Vec3& p,
                              Distance2& distance2, double& best_d2, int& best);

  int build_node(std::vector<int>& ids, const std::vector<Vec3>& centres,
                 const std::vector<Box3>& boxes, int begin, int end, Box3* box, int leaf_size);
  Box3 refit_node(int ref);
  void set_child_box(Node& node, int k, const Box3& box);
  static double box_distance2(const Node& node, int k, const Vec3& p);
  static bool box_overlaps(const Node& node, int k, const Box3& b);
  static bool boxes_overlap(const Node& a, int i, const Node& b, int j);
  Box3 child_box(const Node& node, int k) const;

  template <class Visit>
  void leaf_pairs(int ref, Visit& visit) const;
  template <class Visit>
  void self_pairs(int ref, Visit& visit) const;
  template <class Visit>
  static void leaf_cross_pairs(const Bvh& a, int ra, const FloatBox& box_a, const Bvh& b, int rb,
                               const FloatBox& box_b, Visit& visit);
  template <class Visit>
  void cross_pairs(const Bvh& a, int ra, const FloatBox& box_a, const Bvh& b, int rb,
                   const FloatBox& box_b, Visit& visit) const;

  std::vector<Node> nodes_;
  int root_ = 0;                  // child reference of the whole tree
  Box3 bounds_;
  std::vector<int> order_;        // primitive ids in leaf order
  std::vector<int> slot_;         // (primitives) position in order_
  std::vector<Box3> leaf_boxes_;  // primitive boxes in leaf order, exact
};

// ---- template definitions ----

inline double Bvh::box_distance2(const Node& node, int k, const Vec3& p) {
  double d2 = 0.0;
  for (int a = 0; a < 3; ++a) {
    const double below = node.lo[k][a] - p[a], above = p[a] - node.hi[k][a];
    const double d = below > 0.0 ? below : (above > 0.0 ? above : 0.0);
    d2 += d * d;
  }
  return d2;
}

inline bool Bvh::box_overlaps(const Node& node, int k, const Box3& b) {
  return !((node.lo[k][0] > b.max()[0]) | (node.hi[k][0] < b.min()[0]) |
           (node.lo[k][1] > b.max()[1]) | (node.hi[k][1] < b.min()[1]) |
           (node.lo[k][2] > b.max()[2]) | (node.hi[k][2] < b.min()[2]));
}

inline bool Bvh::boxes_overlap(const Node& a, int i, const Node& b, int j) {
  for (int k = 0; k < 3; ++k) {
    if (a.lo[i][k] > b.hi[j][k] || a.hi[i][k] < b.lo[j][k]) return false;
  }
  return true;
}

template <class Visit>
void Bvh::for_each_overlap(const Box3& query, Visit&& visit) const {
  if (order_.empty() || !bounds_.intersects(query)) return;
  int stack[64];
  int top = 0;
  stack[top++] = root_;
  while (top > 0) {
    const int ref = stack[--top];
    if (is_leaf(ref)) {
      const int first = leaf_first(ref);
      unsigned hits = 0;
      for (int k = 0; k < leaf_count(ref); ++k) {
        hits |= static_cast<unsigned>(meet(leaf_boxes_[first + k], query)) << k;
      }
      for (; hits != 0; hits &= hits - 1) visit(order_[first + __builtin_ctz(hits)]);
      continue;
    }
    const Node& node = nodes_[ref];
    if (box_overlaps(node, 1, query)) stack[top++] = node.child[1];
    if (box_overlaps(node, 0, query)) stack[top++] = node.child[0];
  }
}

template <class Visit>
void Bvh::leaf_pairs(int ref, Visit& visit) const {
  const int first = leaf_first(ref), end = first + leaf_count(ref);
  for (int i = first; i < end; ++i) {
    unsigned hits = 0;
    for (int j = i + 1; j < end; ++j) {
      hits |= static_cast<unsigned>(meet(leaf_boxes_[i], leaf_boxes_[j])) << (j - first);
    }
    for (; hits != 0; hits &= hits - 1) visit(order_[i], order_[first + __builtin_ctz(hits)]);
  }
}

template <class Visit>
void Bvh::for_each_self_overlap(Visit&& visit) const {
  if (!order_.empty()) self_pairs(root_, visit);
}

template <class Visit>
void Bvh::self_pairs(int ref, Visit& visit) const {
  if (is_leaf(ref)) {
    leaf_pairs(ref, visit);
    return;
  }
  const Node& node = nodes_[ref];
  self_pairs(node.child[0], visit);
  self_pairs(node.child[1], visit);
  if (boxes_overlap(node, 0, node, 1)) {
    cross_pairs(*this, node.child[0], FloatBox::of(node, 0), *this, node.child[1],
                FloatBox::of(node, 1), visit);
  }
}

template <class Visit>
void Bvh::for_each_overlap_with(const Bvh& other, Visit&& visit) const {
  if (order_.empty() || other.order_.empty() || !bounds_.intersects(other.bounds_)) return;
  cross_pairs(*this, root_, subtree_box(root_), other, other.root_,
              other.subtree_box(other.root_), visit);
}

// Pairs between subtree ra of a and subtree rb of b, whose boxes overlap. An explicit
// stack of subtree pairs with their boxes (single precision, rounded outward); leaf
// primitives are compared in double precision.
template <class Visit>
void Bvh::cross_pairs(const Bvh& a, int ra, const FloatBox& box_a, const Bvh& b, int rb,
                      const FloatBox& box_b, Visit& visit) const {
  struct Task {
    int ra, rb;
    FloatBox ba, bb;
  };
  thread_local std::vector<Task> stack;
  const size_t bottom = stack.size();  // the stack may be in use further up (nested calls)
  stack.push_back({ra, rb, box_a, box_b});
  while (stack.size() > bottom) {
    const Task t = stack.back();
    stack.pop_back();
    const bool leaf_a = is_leaf(t.ra), leaf_b = is_leaf(t.rb);
    if (leaf_a && leaf_b) {
      leaf_cross_pairs(a, t.ra, t.ba, b, t.rb, t.bb, visit);
      continue;
    }
    // Open the inner node with the larger box (or the only inner one).
    const bool open_a = leaf_b || (!leaf_a && t.ba.extent() >= t.bb.extent());
    if (open_a) {
      const Node& n = a.nodes_[t.ra];
      for (int k = 1; k >= 0; --k) {
        const FloatBox child = FloatBox::of(n, k);
        if (child.overlaps(t.bb)) stack.push_back({n.child[k], t.rb, child, t.bb});
      }
    } else {
      const Node& n = b.nodes_[t.rb];
      for (int k = 1; k >= 0; --k) {
        const FloatBox child = FloatBox::of(n, k);
        if (child.overlaps(t.ba)) stack.push_back({t.ra, n.child[k], t.ba, child});
      }
    }
  }
}

// Pairs between leaf ra of a and leaf rb of b (boxes box_a, box_b, rounded outward), in
// the order of a full double loop over both leaves: only primitives whose box meets the
// other leaf's box can overlap one of its primitives, so the loop runs over those alone.
template <class Visit>
void Bvh::leaf_cross_pairs(const Bvh& a, int ra, const FloatBox& box_a, const Bvh& b, int rb,
                           const FloatBox& box_b, Visit& visit) {
  int near_a[7], near_b[7];
  int na = 0, nb = 0;
  for (int i = leaf_first(ra); i < leaf_first(ra) + leaf_count(ra); ++i) {
    near_a[na] = i;
    na += box_b.meets(a.leaf_boxes_[i]);
  }
  if (na == 0) return;
  for (int j = leaf_first(rb); j < leaf_first(rb) + leaf_count(rb); ++j) {
    near_b[nb] = j;
    nb += box_a.meets(b.leaf_boxes_[j]);
  }
  for (int u = 0; u < na; ++u) {
    const Box3& box = a.leaf_boxes_[near_a[u]];
    unsigned hits = 0;
    for (int w = 0; w < nb; ++w) {
      hits |= static_cast<unsigned>(meet(box, b.leaf_boxes_[near_b[w]])) << w;
    }
    for (; hits != 0; hits &= hits - 1) {
      visit(a.order_[near_a[u]], b.order_[near_b[__builtin_ctz(hits)]]);
    }
  }
}

template <class Distance2>
void Bvh::nearest_in_leaf(const std::vector<int>& order, int ref, const Vec3& p,
                          Distance2& distance2, double& best_d2, int& best) {
  for (int k = leaf_first(ref); k < leaf_first(ref) + leaf_count(ref); ++k) {
    const double d2 = distance2(order[k], p);
    if (d2 < best_d2) {
      best_d2 = d2;
      best = order[k];
    }
  }
}

template <class Distance2>
int Bvh::nearest(const Vec3& p, double max_distance2, Distance2&& distance2,
                 double* best_distance2) const {
  int best = -1;
  double best_d2 = max_distance2;
  if (!order_.empty()) {
    struct Entry {
      int ref;
      double d2;  // squared distance from p to the subtree's box
    };
    Entry stack[64];
    int top = 0;
    stack[top++] = {root_, bounds_.squaredExteriorDistance(p)};
    while (top > 0) {
      const Entry e = stack[--top];
      if (e.d2 >= best_d2) continue;
      if (is_leaf(e.ref)) {
        nearest_in_leaf(order_, e.ref, p, distance2, best_d2, best);
        continue;
      }
      // Visit the nearer child first: push it last.
      const Node& node = nodes_[e.ref];
      const double d0 = box_distance2(node, 0, p), d1 = box_distance2(node, 1, p);
      const int near = d0 <= d1 ? 0 : 1;
      const double dn = near == 0 ? d0 : d1, df = near == 0 ? d1 : d0;
      if (df < best_d2) stack[top++] = {node.child[1 - near], df};
      if (dn < best_d2) stack[top++] = {node.child[near], dn};
    }
  }
  *best_distance2 = best_d2;
  return best;
}

}  // namespace tissu
