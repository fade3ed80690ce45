// A four-wide bounding-volume hierarchy for nearest-primitive queries, collapsed from a
// binary Bvh: each node holds up to four children's boxes side by side in single
// precision (rounded outward), so one node visit measures four boxes at once. Answers
// are those of Bvh::nearest. Tested in tests/collision/bvh_test.
#pragma once

#include <xmmintrin.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "collision/bvh.h"

namespace tissu {

class WideBvh {
 public:
  explicit WideBvh(const Bvh& tree);

  // As Bvh::nearest.
  template <class Distance2>
  int nearest(const Vec3& p, double max_distance2, Distance2&& distance2,
              double* best_distance2) const;

 private:
  struct Node {
    float lo[3][4];  // [axis][child], m
    float hi[3][4];
    int child[4];    // >= 0 inner node; < 0 a leaf (Bvh's encoding); unused slots: kEmpty
  };
  static constexpr int kEmpty = 0x7fffffff;
  int collapse(const Bvh& tree, int ref);
  // Squared distance up to which a box may hold something nearer than best_d2.
  static double limit_of(double best_d2, double slack) {
    const double d = std::sqrt(best_d2) + slack;
    return d * d * (1.0 + 1e-6);
  }

  std::vector<Node> nodes_;
  int root_ = kEmpty;
  Box3 bounds_;
  double scale_ = 0.0;  // largest |coordinate| of the bounds, m
  std::vector<int> order_;
};

template <class Distance2>
int WideBvh::nearest(const Vec3& p, double max_distance2, Distance2&& distance2,
                     double* best_distance2) const {
  int best = -1;
  double best_d2 = max_distance2;
  struct Entry {
    int ref;
    float d2;
  };
  Entry stack[128];
  int top = 0;
  if (root_ != kEmpty) stack[top++] = {root_, static_cast<float>(bounds_.squaredExteriorDistance(p))};
  const __m128 vx = _mm_set1_ps(static_cast<float>(p.x()));
  const __m128 vy = _mm_set1_ps(static_cast<float>(p.y()));
  const __m128 vz = _mm_set1_ps(static_cast<float>(p.z()));
  // Box distances in single precision are off by a few units in the last place of the
  // coordinates: boxes are kept unless farther than the best by more than that.
  const double slack = 1e-6 * (p.cwiseAbs().maxCoeff() + scale_);
  while (top > 0) {
    const Entry e = stack[--top];
    if (e.d2 > limit_of(best_d2, slack)) continue;
    if (Bvh::is_leaf(e.ref)) {
      Bvh::nearest_in_leaf(order_, e.ref, p, distance2, best_d2, best);
      continue;
    }
    const Node& node = nodes_[e.ref];
    // The four box distances at once (SSE, part of every x86-64 processor).
    const __m128 zero = _mm_setzero_ps();
    const __m128 bx = _mm_max_ps(_mm_max_ps(_mm_sub_ps(_mm_loadu_ps(node.lo[0]), vx),
                                            _mm_sub_ps(vx, _mm_loadu_ps(node.hi[0]))), zero);
    const __m128 by = _mm_max_ps(_mm_max_ps(_mm_sub_ps(_mm_loadu_ps(node.lo[1]), vy),
                                            _mm_sub_ps(vy, _mm_loadu_ps(node.hi[1]))), zero);
    const __m128 bz = _mm_max_ps(_mm_max_ps(_mm_sub_ps(_mm_loadu_ps(node.lo[2]), vz),
                                            _mm_sub_ps(vz, _mm_loadu_ps(node.hi[2]))), zero);
    alignas(16) float d2[4];
    _mm_store_ps(d2, _mm_add_ps(_mm_add_ps(_mm_mul_ps(bx, bx), _mm_mul_ps(by, by)),
                                _mm_mul_ps(bz, bz)));
    // Push the children within reach, farthest first.
    int order[4] = {0, 1, 2, 3};
    for (int i = 1; i < 4; ++i) {
      for (int j = i; j > 0 && d2[order[j]] > d2[order[j - 1]]; --j) std::swap(order[j], order[j - 1]);
    }
    const double limit = limit_of(best_d2, slack);
    for (int i = 0; i < 4; ++i) {
      const int c = order[i];
      if (node.child[c] != kEmpty && d2[c] <= limit) stack[top++] = {node.child[c], d2[c]};
    }
  }
  *best_distance2 = best_d2;
  return best;
}

}  // namespace tissu
