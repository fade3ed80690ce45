#include "physics/self_barrier.h"

#include <algorithm>
#include <cmath>

#include "collision/primitive_distance.h"

namespace tissu {

namespace {

// Conservative advancement stops once a gap has shrunk to this fraction of its start: a
// line search step closes a pair's gap tenfold at most (Li et al. 2021, additive CCD), so
// that no pair is driven within rounding of touching, where its barrier stalls Newton.
constexpr double kTouchFraction = 0.1;
constexpr int kMaxAdvances = 100;
constexpr int kLeafSize = 4;
// The trees are rebuilt every this many calls of find_pairs and refitted in between (a
// build costs several refits; a refitted tree's boxes overlap more as the cloth folds).
constexpr int kCallsPerBuild = 32;

Box3 grown(Box3 box, double margin) {
  box.min().array() -= margin;
  box.max().array() += margin;
  return box;
}

}  // namespace

void SelfBarrier::begin(const Model& model) {
  pairs_.clear();
  left_out_ = 0;
  model_ = nullptr;
  if (!model.self_collision) return;
  model_ = &model;
  thickness_ = model.self_collision->thickness;
  if (edges_mesh_ != model.mesh_id || edges_.empty()) {
    edges_ = unique_edges(model.triangles);
    edges_mesh_ = model.mesh_id;
    triangle_tree_ = Bvh();
    edge_tree_ = Bvh();
  }
}

template <typename Position>
PairGap SelfBarrier::gap_at(const std::array<int, 4>& ids, bool edge_edge,
                            Position position) const {
  PairGap g;
  g.count = 4;
  const Vec3 p[4] = {position(ids[0]), position(ids[1]), position(ids[2]), position(ids[3])};
  Vec3 between;  // from the second piece's closest point to the first's, m
  if (edge_edge) {
    const SegmentPoints s = closest_between_segments(p[0], p[1], p[2], p[3]);
    between = p[0] + s.s * (p[1] - p[0]) - (p[2] + s.t * (p[3] - p[2]));
    g.split = 2;
    const double w[4] = {1.0 - s.s, s.s, -(1.0 - s.t), -s.t};
    std::copy(w, w + 4, g.weights);
    g.add_segment_params(s.s, 0, 1.0, p[0], p[1]);
    g.add_segment_params(s.t, 2, -1.0, p[2], p[3]);
    g.edges[0] = p[1] - p[0];
    g.edges[1] = p[3] - p[2];
    g.cross_limit = cross_limit_at_rest(model_->rest_uv, ids);
  } else {
    const TrianglePoint c = closest_on_triangle(p[0], p[1], p[2], p[3]);
    between = p[0] - c.point;
    g.split = 1;
    const double w[4] = {1.0, -c.weights[0], -c.weights[1], -c.weights[2]};
    std::copy(w, w + 4, g.weights);
    g.add_triangle_params(c.feature, 1, -1.0, p[1], p[2], p[3]);
  }
  std::copy(ids.begin(), ids.end(), g.vertices);
  const double distance = between.norm();
  g.distance = distance;
  g.d = distance - thickness_;
  // Touching exactly (distance 0): any direction; the barrier is infinite there anyway.
  g.normal = distance > 0.0 ? Vec3(between / distance) : Vec3::UnitZ();
  return g;
}

PairGap SelfBarrier::gap_of_vertices(const std::array<int, 4>& ids, bool edge_edge,
                                     const Vec3List& x) const {
  return gap_at(ids, edge_edge, [&](int i) -> const Vec3& { return x[i]; });
}

bool SelfBarrier::neighbours_at_rest(const Pair& pair, double reach) const {
  const Model& m = *model_;
  const int split = pair.edge_edge ? 2 : 1;
  Eigen::AlignedBox2d a(m.rest_uv[pair.v[0]]), b(m.rest_uv[pair.v[split]]);
  for (int k = 0; k < 4; ++k) (k < split ? a : b).extend(m.rest_uv[pair.v[k]]);
  const Vec2 apart = (a.min() - b.max()).cwiseMax(b.min() - a.max()).cwiseMax(0.0);
  if (apart.norm() >= reach) return false;
  const auto rest = [&](int i) -> Vec3 { return Vec3(m.rest_uv[i].x(), m.rest_uv[i].y(), 0.0); };
  return gap_at(pair.v, pair.edge_edge, rest).d + thickness_ < reach;
}

void SelfBarrier::find_pairs(const Vec3List& from, const Vec3List& to, double dhat) {
  pairs_.clear();
  left_out_ = 0;
  if (!model_) return;
  const Model& m = *model_;
  const double reach = thickness_ + dhat;  // m: pairs closer than this feel the barrier
  const auto path_box = [&](const int* ids, int count) {
    Box3 box(from[ids[0]], from[ids[0]]);
    for (int k = 0; k < count; ++k) {
      box.extend(from[ids[k]]);
      box.extend(to[ids[k]]);
    }
    return box;
  };
  const bool rebuild = calls_since_build_ == 0;
  calls_since_build_ = (calls_since_build_ + 1) % kCallsPerBuild;
  const auto refit = [&](Bvh& tree) {
    if (!rebuild && tree.num_primitives() == static_cast<int>(boxes_.size())) {
      tree.refit(boxes_);
    } else {
      tree.build(boxes_, kLeafSize);
    }
  };
  const auto movable = [&](const std::array<int, 4>& ids) {
    for (int k : ids) {
      if (!m.pinned[k]) return true;
    }
    return false;
  };
  // Pairs that stay beyond dhat on the way and rest neighbours are left out quietly;
  // pairs already too close are counted.
  const auto keep = [&](const Pair& pair) {
    if (!movable(pair.v)) return;
    const double d = gap_of(pair, from).d;
    if (d - closing_bound(pair, from, to) >= dhat || neighbours_at_rest(pair, reach)) return;
    if (d > 0.0) {
      pairs_.push_back(pair);
    } else {
      ++left_out_;
    }
  };
  // Vertices against triangles: each triangle's path box against each vertex's, grown by
  // the reach.
  boxes_.resize(m.triangles.size());
  for (size_t t = 0; t < m.triangles.size(); ++t) boxes_[t] = path_box(m.triangles[t].data(), 3);
  refit(triangle_tree_);
  for (int i = 0; i < m.num_vertices(); ++i) {
    const Box3 box = grown(path_box(&i, 1), reach);
    triangle_tree_.for_each_overlap(box, [&](int t) {
      const Tri& tri = m.triangles[t];
      if (tri[0] == i || tri[1] == i || tri[2] == i) return;
      keep({{i, tri[0], tri[1], tri[2]}, false});
    });
  }
  // Edges against edges: their path boxes grown by half the reach each.
  boxes_.resize(edges_.size());
  for (size_t e = 0; e < edges_.size(); ++e) {
    boxes_[e] = grown(path_box(edges_[e].data(), 2), 0.5 * reach);
  }
  refit(edge_tree_);
  edge_tree_.for_each_self_overlap([&](int e, int f) {
    const auto &a = edges_[std::min(e, f)], &b = edges_[std::max(e, f)];
    if (a[0] == b[0] || a[0] == b[1] || a[1] == b[0] || a[1] == b[1]) return;
    keep({{a[0], a[1], b[0], b[1]}, true});
  });
}

double SelfBarrier::closing_bound(const Pair& pair, const Vec3List& from, const Vec3List& to) {
  // The gap falls no faster than the pair's largest motion about its mean on each side.
  Vec3 u[4], mean = Vec3::Zero();
  for (int k = 0; k < 4; ++k) {
    u[k] = to[pair.v[k]] - from[pair.v[k]];
    mean += 0.25 * u[k];
  }
  const int split = pair.edge_edge ? 2 : 1;
  double side[2] = {0.0, 0.0};
  for (int k = 0; k < 4; ++k) {
    side[k < split ? 0 : 1] = std::max(side[k < split ? 0 : 1], (u[k] - mean).norm());
  }
  return side[0] + side[1];
}

double SelfBarrier::touch_of(const Pair& pair, const Vec3List& from, const Vec3List& to,
                             double before) const {
  const PairGap g0 = gap_of(pair, from);
  if (g0.d <= 0.0) return 0.0;
  const double speed = closing_bound(pair, from, to);  // m per unit of t
  if (speed <= 0.0 || g0.d >= speed * before) return before;
  double t = 0.0, d = g0.d;
  for (int k = 0; k < kMaxAdvances && d > kTouchFraction * g0.d; ++k) {
    t += d / speed;
    if (t >= before) return before;
    const auto along = [&](int i) -> Vec3 { return from[i] + t * (to[i] - from[i]); };
    d = gap_at(pair.v, pair.edge_edge, along).d;
  }
  return t;
}

double SelfBarrier::first_touch(const Vec3List& from, const Vec3List& to) const {
  double first = 1.0;
  for (const Pair& pair : pairs_) {
    first = std::min(first, touch_of(pair, from, to, first));
    if (first == 0.0) break;
  }
  return first;
}

std::vector<std::array<int, 4>> SelfBarrier::touching_pairs(const Vec3List& from,
                                                            const Vec3List& to) const {
  std::vector<std::array<int, 4>> found;
  for (const Pair& pair : pairs_) {
    if (touch_of(pair, from, to, 1.0) < 1.0) found.push_back(pair.v);
  }
  return found;
}

}  // namespace tissu
