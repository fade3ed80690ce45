#include "physics/mesh_barrier.h"

#include <algorithm>
#include <cmath>

#include "collision/closed_surface.h"
#include "collision/primitive_distance.h"

namespace tissu {

// A mesh's convex corners and edges, in the surface's frame (the world at t = 0), with a
// tree over each.
struct MeshFeatureBarrier::Features {
  std::shared_ptr<const ClosedSurface> surface;  // held: its address names it in the cache
  double least_angle = 0.0;  // rad: edges bent less take no part
  std::vector<int> vertices;  // surface vertex ids
  std::vector<int> edges;     // surface edge ids
  Bvh vertex_tree, edge_tree;  // over vertices[k], edges[k]
};

namespace {

// An edge is convex where the far corner of one of its triangles lies below the other's
// plane by more than this fraction of the edge's length (flat edges of a box's face are
// not).
constexpr double kConvexTolerance = 1e-9;

// Conservative advancement stops once a gap has shrunk to this fraction of its start.
constexpr double kTouchFraction = 1e-3;
constexpr int kMaxAdvances = 100;

// The least bend (rad) of an edge whose two faces a cloth edge of length L can span so that
// its middle dips below the surface when its ends are outside the thickness T: about
// L theta / 4 > T. Edges bent half as much take part too; gentler ones (a finely
// tessellated ball under coarser cloth) are left to the vertices' gaps. That holds for one
// edge: a cloth edge across several gentle edges in a row sags by their sum (mesh_barrier.h).
// L (m) is the cloth's longest rest edge.
double least_bend(double longest, double thickness) {
  return longest > 0.0 ? 2.0 * thickness / longest : 0.0;
}

}  // namespace

double feature_thickness(const Model& model, const Obstacle& obstacle) {
  const bool constrained = model.implicit.contact == ContactModel::Constraints;
  return constrained ? 0.5 * obstacle.thickness : obstacle.thickness;
}

MeshFeatureBarrier::MeshFeatureBarrier() = default;
MeshFeatureBarrier::~MeshFeatureBarrier() = default;

const MeshFeatureBarrier::Features& MeshFeatureBarrier::features_of(
    const std::shared_ptr<const ClosedSurface>& shared, double least_angle) {
  for (const auto& f : cache_) {
    if (f->surface == shared && f->least_angle == least_angle) return *f;
  }
  const ClosedSurface& surface = *shared;
  auto f = std::make_unique<Features>();
  f->surface = shared;
  f->least_angle = least_angle;
  const Vec3List& p = surface.vertices();
  const TriList& tris = surface.triangles();
  const auto& edges = surface.edges();
  // Each edge's two triangles (closed and manifold: exactly two).
  std::vector<std::array<int, 2>> sides(edges.size(), {-1, -1});
  for (size_t t = 0; t < tris.size(); ++t) {
    for (int k = 0; k < 3; ++k) {
      auto& s = sides[surface.triangle_edges()[t][k]];
      s[s[0] < 0 ? 0 : 1] = static_cast<int>(t);
    }
  }
  std::vector<bool> corner(p.size(), false);
  for (size_t e = 0; e < edges.size(); ++e) {
    const int a = edges[e][0], b = edges[e][1];
    if (sides[e][1] < 0) continue;
    const Tri& other = tris[sides[e][1]];
    int far = other[0];
    for (int k = 0; k < 3; ++k) {
      if (other[k] != a && other[k] != b) far = other[k];
    }
    const Vec3& n = surface.face_normals()[sides[e][0]];
    const double below = -n.dot(p[far] - p[a]);  // m
    if (below <= kConvexTolerance * (p[b] - p[a]).norm()) continue;
    const double cosine = std::clamp(n.dot(surface.face_normals()[sides[e][1]]), -1.0, 1.0);
    if (std::acos(cosine) <= least_angle) continue;
    f->edges.push_back(static_cast<int>(e));
    corner[a] = corner[b] = true;
  }
  for (size_t v = 0; v < p.size(); ++v) {
    if (corner[v]) f->vertices.push_back(static_cast<int>(v));
  }
  std::vector<Box3> boxes;
  for (const int v : f->vertices) boxes.emplace_back(p[v], p[v]);
  f->vertex_tree.build(boxes, 4);
  boxes.clear();
  for (const int e : f->edges) {
    Box3 box(p[edges[e][0]], p[edges[e][0]]);
    box.extend(p[edges[e][1]]);
    boxes.push_back(box);
  }
  f->edge_tree.build(boxes, 4);
  cache_.push_back(std::move(f));
  return *cache_.back();
}

void MeshFeatureBarrier::begin(const Model& model, double t, double t_end) {
  model_ = &model;
  placed_.clear();
  pairs_.clear();
  left_out_ = 0;
  bool any_mesh = false;
  for (const Obstacle& ob : model.obstacles) any_mesh = any_mesh || ob.kind == ObstacleKind::Mesh;
  if (!any_mesh) return;
  if (cloth_edges_mesh_ != model.mesh_id) {
    cloth_edges_ = unique_edges(model.triangles);
    longest_edge_ = 0.0;
    for (const auto& e : cloth_edges_) {
      longest_edge_ = std::max(longest_edge_, (model.rest_uv[e[0]] - model.rest_uv[e[1]]).norm());
    }
    cloth_edges_mesh_ = model.mesh_id;
  }
  for (size_t o = 0; o < model.obstacles.size(); ++o) {
    const Obstacle& ob = model.obstacles[o];
    if (ob.kind != ObstacleKind::Mesh) continue;
    const Features& f = features_of(ob.surface, least_bend(longest_edge_, ob.thickness));
    if (f.vertices.empty()) continue;
    placed_.push_back({&f, ob.center, ob.center_at(t_end), ob.rotation(t_end), ob.center_at(t),
                       ob.rotation(t), feature_thickness(model, ob), static_cast<int>(o)});
  }
}

template <typename Local>
PairGap MeshFeatureBarrier::gap_at(const Pair& pair, Local local, bool at_start) const {
  const Placed& m = placed_[pair.mesh];
  const ClosedSurface& surface = *m.features->surface;
  const Vec3List& q = surface.vertices();
  PairGap g;
  Vec3 between;  // from the feature to the cloth's closest point, surface frame, m
  if (pair.edge_edge) {
    const auto& e = cloth_edges_[pair.cloth];
    const auto& f = surface.edges()[pair.feature];
    const Vec3 a = local(e[0]), b = local(e[1]);
    const SegmentPoints s = closest_between_segments(a, b, q[f[0]], q[f[1]]);
    between = a + s.s * (b - a) - (q[f[0]] + s.t * (q[f[1]] - q[f[0]]));
    g.count = g.split = 2;
    g.vertices[0] = e[0];
    g.vertices[1] = e[1];
    g.weights[0] = 1.0 - s.s;
    g.weights[1] = s.s;
  } else {
    const Tri& t = model_->triangles[pair.cloth];
    const TrianglePoint c =
        closest_on_triangle(q[pair.feature], local(t[0]), local(t[1]), local(t[2]));
    between = c.point - q[pair.feature];
    g.count = g.split = 3;
    for (int k = 0; k < 3; ++k) {
      g.vertices[k] = t[k];
      g.weights[k] = c.weights[k];
    }
  }
  const double distance = between.norm();
  g.d = distance - m.thickness;
  // Touching exactly (distance 0): any direction; the barrier is infinite there anyway.
  g.normal = (at_start ? m.start_rotation : m.rotation) *
             (distance > 0.0 ? Vec3(between / distance) : Vec3::UnitZ());
  return g;
}

void MeshFeatureBarrier::for_each_contact_at_start(
    const Vec3List& x, double t,
    const std::function<void(const PairGap&, int, const Vec3&)>& visit) const {
  for (const Pair& p : pairs_) {
    const Placed& m = placed_[p.mesh];
    const PairGap g = gap_at(p, [&](int i) { return m.local_at_start(x[i]); }, true);
    Vec3 point = Vec3::Zero();  // the cloth's closest point, m
    for (int k = 0; k < g.count; ++k) point += g.weights[k] * x[g.vertices[k]];
    visit(g, m.obstacle, model_->obstacles[m.obstacle].point_velocity(point, t));
  }
}

PairGap MeshFeatureBarrier::gap_of(const Pair& pair, const Vec3List& x) const {
  const Placed& m = placed_[pair.mesh];
  return gap_at(pair, [&](int i) { return m.local(x[i]); });
}

Vec3 MeshFeatureBarrier::carried(int mesh, const Vec3& p, double reach) const {
  const Placed& m = placed_[mesh];
  const Vec3 local = m.local_at_start(p);
  const Vec3 moved = m.center + m.rotation * (local - m.rest_center);
  const double band = m.thickness + reach + (moved - p).norm();  // m
  return m.features->surface->closest_within(local, band).distance < band ? moved : p;
}

void MeshFeatureBarrier::find_pairs(const Vec3List& from, const Vec3List& to, double dhat,
                                    bool from_start) {
  pairs_.clear();
  left_out_ = 0;
  if (placed_.empty()) return;
  const Model& model = *model_;
  for (size_t o = 0; o < placed_.size(); ++o) {
    const Placed& m = placed_[o];
    const Features& f = *m.features;
    const auto local_from = [&](int i) {
      return from_start ? m.local_at_start(from[i]) : m.local(from[i]);
    };
    const double margin = dhat + m.thickness;  // m
    // The box of a cloth primitive's vertices over their paths, grown by the margin.
    const auto path_box = [&](const int* ids, int count) {
      Box3 box(local_from(ids[0]), local_from(ids[0]));
      for (int k = 0; k < count; ++k) {
        box.extend(local_from(ids[k]));
        box.extend(m.local(to[ids[k]]));
      }
      box.min().array() -= margin;
      box.max().array() += margin;
      return box;
    };
    const auto all_pinned = [&](const int* ids, int count) {
      for (int k = 0; k < count; ++k) {
        if (!model.pinned[ids[k]]) return false;
      }
      return true;
    };
    const auto keep = [&](const Pair& pair) {
      if (gap_at(pair, local_from).d > 0.0) {
        pairs_.push_back(pair);
      } else {
        ++left_out_;
      }
    };
    const Box3& bounds = f.vertex_tree.bounds();
    for (int t = 0; t < model.num_triangles(); ++t) {
      const Tri& tri = model.triangles[t];
      if (all_pinned(tri.data(), 3)) continue;
      const Box3 box = path_box(tri.data(), 3);
      if (!box.intersects(bounds)) continue;
      f.vertex_tree.for_each_overlap(box, [&](int k) {
        keep({static_cast<int>(o), f.vertices[k], t, false});
      });
    }
    for (size_t e = 0; e < cloth_edges_.size(); ++e) {
      const int* ids = cloth_edges_[e].data();
      if (all_pinned(ids, 2)) continue;
      const Box3 box = path_box(ids, 2);
      if (!box.intersects(bounds)) continue;
      f.edge_tree.for_each_overlap(box, [&](int k) {
        keep({static_cast<int>(o), f.edges[k], static_cast<int>(e), true});
      });
    }
  }
}

template <typename Start, typename End>
double MeshFeatureBarrier::touch_along(const Pair& pair, Start start, End end,
                                       double limit) const {
  const PairGap g0 = gap_at(pair, start);
  if (g0.d <= 0.0) return 0.0;
  double speed = 0.0;  // m per unit of t: the gap falls at most this fast
  for (int k = 0; k < g0.count; ++k) {
    speed = std::max(speed, (end(g0.vertices[k]) - start(g0.vertices[k])).norm());
  }
  if (speed <= 0.0 || g0.d >= speed * limit) return limit;
  double t = 0.0, d = g0.d;
  for (int k = 0; k < kMaxAdvances && d > kTouchFraction * g0.d; ++k) {
    t += d / speed;
    if (t >= limit) return limit;
    d = gap_at(pair, [&](int i) -> Vec3 { return start(i) + t * (end(i) - start(i)); }).d;
  }
  return t;
}

double MeshFeatureBarrier::first_touch(const Vec3List& x, const Vec3List& u) const {
  double first = 1.0;
  for (const Pair& pair : pairs_) {
    const Placed& m = placed_[pair.mesh];
    first = touch_along(
        pair, [&](int i) { return m.local(x[i]); },
        [&](int i) { return m.local(x[i] + u[i]); }, first);
  }
  return first;
}

double MeshFeatureBarrier::first_touch_over_step(const Vec3List& x_n, const Vec3List& x_end,
                                                 int* mesh) const {
  double first = 1.0;
  *mesh = -1;
  for (const Pair& pair : pairs_) {
    const Placed& m = placed_[pair.mesh];
    const double t = touch_along(
        pair, [&](int i) { return m.local_at_start(x_n[i]); },
        [&](int i) { return m.local(x_end[i]); }, first);
    if (t < first) {
      first = t;
      *mesh = pair.mesh;
    }
  }
  return first;
}

}  // namespace tissu
