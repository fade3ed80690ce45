#include "physics/cloth_contact.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <random>

#include "collision/bvh.h"
#include "core/cpu_clock.h"
#include "collision/ccd.h"
#include "collision/closed_surface.h"
#include "collision/primitive_distance.h"
#include "physics/mesh_barrier.h"
#include "physics/step_scratch.h"

namespace tissu {

namespace {

// Repulsion of a pair already closer than its thickness: this fraction of the shortfall
// per step (Bridson et al. 2002 use the same tenth).
constexpr double kRepulsion = 0.1;
// Continuous detection counts primitives closer than this as touching, m.
constexpr double kTouch = 1e-9;
// A vertex this close to an obstacle's triangle at the start of a step rests on it, m.
constexpr double kClear = 1e-6;
// Rounds of plain impulses before impacts are handled as zones, rounds of zone solves
// before zones move rigidly, and rigid rounds before a zone is held at its start.
constexpr int kImpulseRounds = 4;
constexpr int kZoneRounds = 12;
constexpr int kRigidRounds = 4;
// Projected Gauss-Seidel sweeps of one zone solve, at most.
constexpr int kZoneSweeps = 200;
// Primitives per leaf of the cloth's trees (overlap queries of many boxes).
constexpr int kLeafSize = 6;
// A vertex's region covers its motion over this many steps like the current one.
constexpr double kRegionSteps = 128.0;  // on the fold bench: 16 -> 48 ns/tri, 64 -> 28, 128 -> 24

// A pair of primitives watched for contact. Points: cloth vertices 0 .. V-1, then the
// obstacle vertices in use (V + k).
struct Pair {
  std::array<int, 4> p;     // vertex-triangle: vertex, triangle corners; edge-edge: two edges
  bool edge_edge = false;
  bool repel = true;        // proximity response (false: kept from crossing only)
  int obstacle = -1;        // -1 cloth against cloth
  double thickness = 0.0;   // m
  double friction = 0.0;
  double built_distance = 0.0;  // m, between the primitives when the lists were built
};

// The closest points of a pair: gap = sum_k weights[k] x_k, from the second primitive to
// the first.
struct Closest {
  double weights[4];
  Vec3 gap;
  double distance;
};

Closest closest_of(const Pair& pair, const Vec3* x[4]) {
  Closest c;
  if (pair.edge_edge) {
    const SegmentPoints s = closest_between_segments(*x[0], *x[1], *x[2], *x[3]);
    c.weights[0] = 1.0 - s.s;
    c.weights[1] = s.s;
    c.weights[2] = -(1.0 - s.t);
    c.weights[3] = -s.t;
  } else {
    const TrianglePoint q = closest_on_triangle(*x[0], *x[1], *x[2], *x[3]);
    c.weights[0] = 1.0;
    for (int k = 0; k < 3; ++k) c.weights[k + 1] = -q.weights[k];
  }
  c.gap = Vec3::Zero();
  for (int k = 0; k < 4; ++k) c.gap += c.weights[k] * *x[k];
  c.distance = c.gap.norm();
  return c;
}

// Whether an edge-edge pair's closest points lie at an end of either edge.
bool at_an_end(const Closest& c) {
  return c.weights[0] == 1.0 || c.weights[1] == 1.0 || c.weights[2] == -1.0 || c.weights[3] == -1.0;
}

// A non-penetration constraint of an impact zone: n . sum_k w_k x1_k >= separation.
struct Constraint {
  std::array<int, 4> p;
  double weights[4];
  Vec3 normal;
  double separation;  // m
  double lambda = 0.0;  // accumulated correction, m (mass-weighted)
};

double box_distance(const Box3& a, const Box3& b) {
  const Vec3 gap = (a.min() - b.max()).cwiseMax(b.min() - a.max()).cwiseMax(0.0);
  return gap.norm();
}

// Union-find over cloth vertices (impact zones).
struct Zones {
  std::vector<int> parent;
  void reset(int n) {
    parent.resize(n);
    std::iota(parent.begin(), parent.end(), 0);
  }
  int find(int i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  }
  void join(int a, int b) {
    a = find(a);
    b = find(b);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  }
};

}  // namespace

void ContactStats::add(const ContactStats& other) {
  candidates = std::max(candidates, other.candidates);
  rebuilt = rebuilt || other.rebuilt;
  calls += other.calls;
  builds += other.builds;
  build_distances += other.build_distances;
  proximities += other.proximities;
  impacts += other.impacts;
  rounds += other.rounds;
  zones += other.zones;
  rigid_zones += other.rigid_zones;
  unresolved = other.unresolved;
}

void run_collision_stage(const Model& model, double t0, double dt, const Vec3List& x0,
                         State& state, Workspace& ws) {
  StepScratch& scratch = scratch_of(ws);
  if (!scratch.contact) scratch.contact = std::make_shared<ClothContact>();
  const double start = thread_cpu_seconds();
  ws.contact.add(scratch.contact->resolve(model, t0, dt, x0, state.x, state.v));
  ws.contact_seconds += thread_cpu_seconds() - start;
}

bool needs_cloth_contact(const Model& model) {
  if (model.self_collision) return true;
  for (const Obstacle& ob : model.obstacles) {
    if (ob.kind == ObstacleKind::Mesh) return true;
  }
  return false;
}

struct ClothContact::Impl {
  // ---- the model's topology (built once per mesh) ----
  uint64_t mesh_id = 0;
  int V = 0;
  std::vector<std::array<int, 2>> edges;
  Bvh triangle_tree, edge_tree;
  double mean_edge = 0.0;  // m

  // ---- mesh obstacles ----
  struct MeshFeatures {
    int obstacle = -1;
    const ClosedSurface* surface = nullptr;
    std::vector<int> kinematic_of;  // (surface vertices) point id - V, or -1
    Vec3 built_center;              // placement when the lists were built
    Mat3 built_rotation;
    double margin = 0.0;            // m, how far it may move before a rebuild
    Vec3 center0, center1;          // placement at the step's start and end
    Mat3 rotation0, rotation1;
    double moved = 0.0;             // m, largest displacement since the build (this step)
  };
  std::vector<MeshFeatures> meshes;
  // Obstacle vertices in use: surface position (t = 0), owner, positions this step.
  Vec3List kinematic_body;
  std::vector<int> kinematic_mesh;    // index into meshes
  std::vector<int> kinematic_vertex;  // vertex id in its surface
  Vec3List k0, k1;

  // ---- candidate lists ----
  std::vector<Pair> pairs;
  // What the broad phase found in a build, and its sorting (buffers reused).
  std::vector<Box3> query_boxes;
  std::vector<std::array<int, 2>> found_pairs, sorted_pairs;
  std::vector<int> bucket_first, bucket_next;
  // What select_active reads of each pair, packed: its points, whether it is an edge pair
  // and counts world displacements (an obstacle pair), and how far its points may move
  // together before it may matter (distance at the build less its threshold, rounded
  // down), m.
  struct Watch {
    std::array<int, 4> p;
    float slack;
    bool edge_edge;
    bool world;
  };
  std::vector<Watch> watches;
  // Where each vertex may go before the lists are rebuilt: for pairs of cloth primitives,
  // in a frame that moves with the cloth's mean displacement (pairwise distances do not
  // see a common translation, so a falling sheet keeps small regions); for pairs with an
  // obstacle's features, in the world.
  std::vector<Box3> region, world_region;  // (V)
  Vec3List built_at;                       // (V) positions when the lists were built
  Vec3 frame_start = Vec3::Zero();         // the frame's offset at this step's start, m
  Vec3 frame_end = Vec3::Zero();           // and at its end
  // The last step's start time and length (s), and the frame's offset at its start (m):
  // the implicit integrators run the stage again on the same step after solving it again
  // from the same start (implicit.cpp, substep), where the frame has that offset again.
  double last_t0 = NAN, last_dt = NAN;
  Vec3 last_frame_start = Vec3::Zero();
  std::vector<double> moved, moved_world;  // (V) largest distance from built_at this step, m
  bool built = false;
  // When to look at a pair again (cloth pairs only, no mesh obstacle): a pair found apart
  // at step s, with a(s) + b(s) below its slack (a, b: the farthest its two sides' points
  // have moved from where the lists were built), cannot have its slack used up before
  //   a(t) + b(t) <= a(s) + b(s) + 2 (swept(t) - swept(s)) + 2 reach(t) >= slack,
  // where swept adds up, step by step, the largest motion of any vertex between the
  // starts of consecutive steps (in the frame), and reach(t) is the largest motion
  // within step t (a vertex's start at t is at most swept(t) - swept(s) from its start at
  // s, and its end at most reach(t) from its start at t). Each pair waits in the bucket of
  // wake = swept(s) + (slack - a(s) - b(s)) / 2 and is looked at again (with the exact
  // test of select_active) only when swept + reach reaches its bucket: the many pairs far
  // apart cost nothing per step, only those in or near contact do.
  bool scheduled = false;           // the lists hold cloth pairs only: the schedule is used
  double swept = 0.0;               // m, since the build
  double reach = 0.0;               // m, this step
  Vec3List last_start;              // (V) start of the previous step in the frame, m
  double quantum = 0.0;             // m, bucket width of wake values
  int64_t drained = 0;              // buckets up to this one are empty
  static constexpr int kBuckets = 1024;
  std::vector<std::vector<int>> buckets;  // (kBuckets) ring: bucket key % kBuckets
  std::vector<int> due;             // pairs to look at in the next step whatever it does
  std::vector<int> woken;           // the pairs looked at this step
  std::vector<uint64_t> active_bits;  // (watches / 64) the active pairs, as a bit set
  bool fresh = false;               // the lists were just built: every pair is looked at

  // ---- per step ----
  const Model* model = nullptr;
  double dt = 0.0;
  const Vec3List* x0 = nullptr;
  Vec3List* x1 = nullptr;
  Vec3List* v = nullptr;
  std::vector<int> active;        // pairs that may touch this step
  std::vector<double> start_distance;  // (active) at x0, m
  std::vector<Constraint> constraints;
  Zones zones;
  // Vertices resting on an obstacle at the end of the step: the stage never pushes them
  // into it (each velocity change is followed by the obstacle's response).
  struct Support {
    Vec3 normal;            // outward, unit
    double offset;          // normal . x1 may not fall below this, m
    Vec3 surface_velocity;  // m/s
  };
  std::vector<int> support_of;  // (V) index into supports, or -1
  std::vector<Support> supports;
  std::vector<int> touched;     // vertices of the active pairs (find_supports)
  // Detection rounds: after the first of a step, a pair is checked again only when one of
  // its vertices changed since the round before (else it still cannot collide).
  int detection = 0;
  bool full_detection = true;
  std::vector<int> changed_at;  // (V) the detection round after which it last moved
  std::vector<double> motion_of;   // (V) |x1 - x0| at the round motion_round says, m
  std::vector<int> motion_round;   // (V) the detection round motion_of was measured in
  bool project_supports = true;  // kick() holds supported vertices out of their obstacle

  const Vec3& start(int id) const { return id < V ? (*x0)[id] : k0[id - V]; }
  const Vec3& end(int id) const { return id < V ? (*x1)[id] : k1[id - V]; }
  double inv_mass(int id) const { return id < V ? model->inv_mass[id] : 0.0; }

  void prepare_topology(const Model& m);
  void place_meshes(double t0, double t1);
  bool lists_valid();
  bool ends_in_regions() const;
  void rebuild();
  void add_self_pairs(double reach);
  void sort_id_pairs(std::vector<std::array<int, 2>>& list, int count);
  // Tests: the broad phase's pairs in an order shuffled by this seed (0: as found).
  uint64_t shuffle_seed = 0;
  template <class T>
  void shuffle_found(std::vector<T>& list) {
    if (shuffle_seed == 0) return;
    std::mt19937_64 random(shuffle_seed++);
    std::shuffle(list.begin(), list.end(), random);
  }
  void add_mesh_pairs(MeshFeatures& mesh, double reach);
  int kinematic_point(MeshFeatures& mesh, int mesh_index, int vertex);
  Vec3 obstacle_normal(const Pair& pair) const;
  void select_active();
  void start_schedule();
  void wait(int pair, double a, double b);
  bool apart(int pair, double* a, double* b) const;
  void find_supports(double t1);
  void measure_start();
  void proximity(ContactStats& stats);
  void collide(ContactStats& stats);
  int detect(std::vector<Constraint>& found);
  double motion_in_round(int id, int round);
  void push_apart(const Constraint& c);
  bool solve_zones();
  void move_rigidly(const std::vector<int>& zone_vertices, int mesh_index);
  ContactStats resolve(double t0);

  // Changes the velocity of point id by dv (m/s), and its end position by dt dv; a vertex
  // resting on an obstacle is then held out of it, as the obstacle's response would.
  void kick(int id, const Vec3& dv) {
    if (id >= V || model->inv_mass[id] == 0.0) return;
    (*v)[id] += dv;
    (*x1)[id] += dt * dv;
    changed_at[id] = detection;
    if (!project_supports) return;
    const int s = support_of[id];
    if (s < 0) return;
    const Support& support = supports[s];
    const double below = support.offset - support.normal.dot((*x1)[id]);
    if (below > 0.0) (*x1)[id] += below * support.normal;
    const double inward = support.normal.dot((*v)[id] - support.surface_velocity);
    if (inward < 0.0) (*v)[id] -= inward * support.normal;
  }
  double effective_inverse_mass(const std::array<int, 4>& p, const double w[4]) const {
    double sum = 0.0;
    for (int k = 0; k < 4; ++k) sum += w[k] * w[k] * inv_mass(p[k]);
    return sum;
  }
};

void ClothContact::Impl::prepare_topology(const Model& m) {
  if (mesh_id == m.mesh_id && V == m.num_vertices()) return;
  mesh_id = m.mesh_id;
  V = m.num_vertices();
  edges = unique_edges(m.triangles);
  double total = 0.0;
  for (const auto& e : edges) total += (m.rest_uv[e[0]] - m.rest_uv[e[1]]).norm();
  mean_edge = edges.empty() ? 0.0 : total / edges.size();
  triangle_tree = Bvh();
  edge_tree = Bvh();
  built = false;
  support_of.assign(V, -1);
  touched.clear();
  meshes.clear();
  for (size_t o = 0; o < m.obstacles.size(); ++o) {
    if (m.obstacles[o].kind != ObstacleKind::Mesh) continue;
    MeshFeatures f;
    f.obstacle = static_cast<int>(o);
    f.surface = m.obstacles[o].surface.get();
    f.kinematic_of.assign(f.surface->vertices().size(), -1);
    meshes.push_back(std::move(f));
  }
}

void ClothContact::Impl::place_meshes(double t0, double t1) {
  for (MeshFeatures& f : meshes) {
    const Obstacle& ob = model->obstacles[f.obstacle];
    f.center0 = ob.center_at(t0);
    f.center1 = ob.center_at(t1);
    f.rotation0 = ob.rotation(t0);
    f.rotation1 = ob.rotation(t1);
  }
  for (size_t k = 0; k < kinematic_body.size(); ++k) {
    const MeshFeatures& f = meshes[kinematic_mesh[k]];
    if (!model->obstacles[f.obstacle].motion.moves()) continue;  // placed when added
    const Vec3 local = kinematic_body[k] - model->obstacles[f.obstacle].center;
    k0[k] = f.center0 + f.rotation0 * local;
    k1[k] = f.center1 + f.rotation1 * local;
  }
}

// Every vertex still in its regions and every obstacle within its margin; also measures
// how far each moved since the lists were built.
bool ClothContact::Impl::lists_valid() {
  // The frame follows the mean displacement of the free vertices over the step.
  Vec3 mean = Vec3::Zero();
  int free = 0;
  for (int i = 0; i < V; ++i) {
    if (model->inv_mass[i] == 0.0) continue;
    mean += (*x1)[i] - (*x0)[i];
    ++free;
  }
  if (free > 0) mean /= free;
  frame_end = frame_start + mean;
  moved.resize(V);  // every entry is set below, or by rebuild()
  moved_world.resize(V);
  if (!built) return false;
  bool valid = true;
  const bool world = !meshes.empty();
  double step2 = 0.0, within2 = 0.0;  // m^2, the schedule's motions (largest squared)
  for (int i = 0; i < V; ++i) {
    const Vec3 a = (*x0)[i] - frame_start, b = (*x1)[i] - frame_end;
    moved[i] = std::sqrt(std::max((a - built_at[i]).squaredNorm(), (b - built_at[i]).squaredNorm()));
    if (valid && !(region[i].contains(a) && region[i].contains(b))) valid = false;
    if (scheduled) {
      step2 = std::max(step2, (a - last_start[i]).squaredNorm());
      within2 = std::max(within2, (b - a).squaredNorm());
      last_start[i] = a;
    }
    if (!world) continue;
    const Vec3 &wa = (*x0)[i], &wb = (*x1)[i];
    moved_world[i] =
        std::sqrt(std::max((wa - built_at[i]).squaredNorm(), (wb - built_at[i]).squaredNorm()));
    if (valid && !(world_region[i].contains(wa) && world_region[i].contains(wb))) valid = false;
  }
  for (MeshFeatures& f : meshes) {
    // A rigid motion moves a box farthest at one of its corners.
    const Obstacle& ob = model->obstacles[f.obstacle];
    const Box3 box = f.surface->bounds();
    double most = 0.0;
    for (int c = 0; c < 8; ++c) {
      const Vec3 corner(c & 1 ? box.max().x() : box.min().x(), c & 2 ? box.max().y() : box.min().y(),
                        c & 4 ? box.max().z() : box.min().z());
      const Vec3 local = corner - ob.center;
      const Vec3 then = f.built_center + f.built_rotation * local;
      most = std::max({most, (f.center0 + f.rotation0 * local - then).norm(),
                       (f.center1 + f.rotation1 * local - then).norm()});
    }
    f.moved = most;
    if (most > f.margin) valid = false;
  }
  if (scheduled) {
    swept += std::sqrt(step2);
    reach = std::sqrt(within2);
  }
  return valid;
}

// After the stage: the end positions it produced are still in their regions (else the
// lists may miss a pair and are rebuilt). Only the vertices of active pairs can have
// moved since the regions were checked (lists_valid) or made (rebuild).
bool ClothContact::Impl::ends_in_regions() const {
  for (int i : touched) {
    if (!region[i].contains((*x1)[i] - frame_end)) return false;
    if (!meshes.empty() && !world_region[i].contains((*x1)[i])) return false;
  }
  return true;
}

int ClothContact::Impl::kinematic_point(MeshFeatures& mesh, int mesh_index, int vertex) {
  int& k = mesh.kinematic_of[vertex];
  if (k < 0) {
    k = static_cast<int>(kinematic_body.size());
    kinematic_body.push_back(mesh.surface->vertices()[vertex]);
    kinematic_mesh.push_back(mesh_index);
    kinematic_vertex.push_back(vertex);
    const Vec3 local = kinematic_body.back() - model->obstacles[mesh.obstacle].center;
    k0.push_back(mesh.center0 + mesh.rotation0 * local);
    k1.push_back(mesh.center1 + mesh.rotation1 * local);
  }
  return V + k;
}

// The outward normal of an obstacle pair's surface feature at the step's start: the
// vertex normal of an obstacle vertex, the mean of an obstacle edge's two ends'.
Vec3 ClothContact::Impl::obstacle_normal(const Pair& pair) const {
  Vec3 n = Vec3::Zero();
  for (int id : pair.p) {
    if (id < V) continue;
    const int k = id - V;
    const MeshFeatures& f = meshes[kinematic_mesh[k]];
    n += f.rotation0 * f.surface->vertex_normals()[kinematic_vertex[k]].normalized();
  }
  return n.normalized();
}

void ClothContact::Impl::rebuild() {
  const Model& m = *model;
  double thickest = m.self_collision ? m.self_collision->thickness : 0.0;
  for (const MeshFeatures& f : meshes) thickest = std::max(thickest, m.obstacles[f.obstacle].thickness);
  const double margin_min = std::max(0.25 * thickest, 0.05 * mean_edge);
  const double margin_max = std::max(thickest, 0.25 * mean_edge);
  region.resize(V);
  world_region.resize(V);
  built_at = *x0;
  // The frame starts here: its offset is zero at x0 and the step's mean displacement at x1.
  frame_end -= frame_start;
  frame_start = Vec3::Zero();
  auto grown = [&](const Vec3& a, const Vec3& b) {
    const double margin = std::clamp(kRegionSteps * (b - a).norm(), margin_min, margin_max);
    Box3 box(a);
    box.extend(b);
    return Box3(box.min() - Vec3::Constant(margin), box.max() + Vec3::Constant(margin));
  };
  for (int i = 0; i < V; ++i) {
    region[i] = grown((*x0)[i], (*x1)[i] - frame_end);
    world_region[i] = grown((*x0)[i], (*x1)[i]);
  }
  pairs.clear();
  for (size_t k = 0; k < kinematic_body.size(); ++k) {
    meshes[kinematic_mesh[k]].kinematic_of[kinematic_vertex[k]] = -1;
  }
  kinematic_body.clear();
  kinematic_mesh.clear();
  kinematic_vertex.clear();
  k0.clear();
  k1.clear();
  if (m.self_collision) add_self_pairs(m.self_collision->thickness);
  for (size_t k = 0; k < meshes.size(); ++k) {
    MeshFeatures& f = meshes[k];
    // The obstacle's own motion over the step decides how far it may go before a rebuild.
    f.built_center = f.center0;
    f.built_rotation = f.rotation0;
    double motion = 0.0;
    {
      const Obstacle& ob = m.obstacles[f.obstacle];
      const Box3 box = f.surface->bounds();
      for (int c = 0; c < 8; ++c) {
        const Vec3 corner(c & 1 ? box.max().x() : box.min().x(), c & 2 ? box.max().y() : box.min().y(),
                          c & 4 ? box.max().z() : box.min().z());
        const Vec3 local = corner - ob.center;
        motion = std::max(motion, (f.center1 + f.rotation1 * local - f.center0 - f.rotation0 * local).norm());
      }
    }
    f.margin = motion > 0.0 ? std::clamp(kRegionSteps * motion, margin_min, margin_max) : 0.0;
    f.moved = motion;  // measured from this build
    // An implicit solve holds the cloth off the mesh's corners and edges itself, past
    // feature_thickness: the stage keeps that layer, not a thicker one the solve lets
    // edges into.
    const Obstacle& ob = m.obstacles[f.obstacle];
    add_mesh_pairs(f, is_explicit(m.integrator) ? ob.thickness : feature_thickness(m, ob));
  }
  watches.resize(pairs.size());
  for (size_t k = 0; k < pairs.size(); ++k) {
    const Pair& pair = pairs[k];
    const double slack = pair.built_distance - (pair.repel ? pair.thickness : 0.0) - kTouch;
    watches[k] = {pair.p, static_cast<float>(slack) - static_cast<float>(1e-6 * std::fabs(slack) + 1e-12),
                  pair.edge_edge, pair.obstacle >= 0};
  }
  // Displacement since the build (the build is at x0).
  for (int i = 0; i < V; ++i) {
    moved[i] = ((*x1)[i] - frame_end - (*x0)[i]).norm();
    moved_world[i] = ((*x1)[i] - (*x0)[i]).norm();
  }
  built = true;
  start_schedule();
}

// A new schedule from the build at x0: every pair is looked at in this step.
void ClothContact::Impl::start_schedule() {
  fresh = true;
  scheduled = meshes.empty();
  if (!scheduled) return;
  swept = 0.0;
  reach = 0.0;
  for (int i = 0; i < V; ++i) reach = std::max(reach, moved[i]);
  last_start = *x0;  // the frame starts at x0
  // Wake values lie at most half the largest slack beyond swept: kBuckets - 4 buckets.
  double widest = 0.0;
  for (const Watch& w : watches) widest = std::max(widest, static_cast<double>(w.slack));
  quantum = std::max(0.5 * widest / (kBuckets - 4), 1e-9);
  buckets.resize(kBuckets);
  for (std::vector<int>& b : buckets) b.clear();
  due.clear();
  drained = -1;
}

void ClothContact::Impl::add_self_pairs(double thickness) {
  const Model& m = *model;
  const double half = 0.5 * thickness;
  const Vec3 pad = Vec3::Constant(half);
  std::vector<Box3> boxes(m.triangles.size());
  for (size_t t = 0; t < m.triangles.size(); ++t) {
    const Tri& tri = m.triangles[t];
    Box3 b = region[tri[0]];
    b.extend(region[tri[1]]);
    b.extend(region[tri[2]]);
    boxes[t] = Box3(b.min() - pad, b.max() + pad);
  }
  if (triangle_tree.empty()) {
    triangle_tree.build(boxes, kLeafSize);
  } else {
    triangle_tree.refit(boxes);
  }
  std::vector<Box3> edge_boxes(edges.size());
  for (size_t e = 0; e < edges.size(); ++e) {
    Box3 b = region[edges[e][0]];
    b.extend(region[edges[e][1]]);
    edge_boxes[e] = Box3(b.min() - pad, b.max() + pad);
  }
  const double friction = m.self_collision->friction;
  auto rest = [&](int id) { return Vec3(m.rest_uv[id].x(), m.rest_uv[id].y(), 0.0); };
  // Neighbours in the fabric: closer than the thickness in the rest shape (a box test
  // settles almost every pair).
  auto apart_at_rest = [&](const Pair& pair) {
    Eigen::AlignedBox2d a(m.rest_uv[pair.p[0]]), b(m.rest_uv[pair.p[pair.edge_edge ? 2 : 1]]);
    if (pair.edge_edge) {
      a.extend(m.rest_uv[pair.p[1]]);
      b.extend(m.rest_uv[pair.p[3]]);
    } else {
      b.extend(m.rest_uv[pair.p[2]]);
      b.extend(m.rest_uv[pair.p[3]]);
    }
    const Vec2 gap = (a.min() - b.max()).cwiseMax(b.min() - a.max()).cwiseMax(0.0);
    if (gap.norm() >= thickness) return true;
    const Vec3 r0 = rest(pair.p[0]), r1 = rest(pair.p[1]), r2 = rest(pair.p[2]), r3 = rest(pair.p[3]);
    const Vec3* r[4] = {&r0, &r1, &r2, &r3};
    return closest_of(pair, r).distance >= thickness;
  };
  auto movable = [&](std::initializer_list<int> ids) {
    for (int id : ids) {
      if (m.inv_mass[id] > 0.0) return true;
    }
    return false;
  };
  // The pairs go into the lists in a canonical order (by their primitives' ids), not in
  // the order the broad phase finds them: the order of the lists is the order in which
  // proximity and detection apply their impulses, so the stage's result depends only on
  // which pairs were found.
  // Vertex against triangle: the pairs (vertex, triangle) by vertex, then triangle id.
  std::vector<Box3>& vertex_boxes = query_boxes;
  vertex_boxes.resize(V);
  for (int i = 0; i < V; ++i) vertex_boxes[i] = Box3(region[i].min() - pad, region[i].max() + pad);
  std::vector<std::array<int, 2>>& hits = found_pairs;
  hits.clear();
  auto vertex_triangle = [&](int i, int t) {
    const Tri& tri = m.triangles[t];
    if (tri[0] == i || tri[1] == i || tri[2] == i) return;
    if (!movable({i, tri[0], tri[1], tri[2]})) return;
    Box3 tb = region[tri[0]];
    tb.extend(region[tri[1]]);
    tb.extend(region[tri[2]]);
    if (box_distance(region[i], tb) >= thickness) return;
    hits.push_back({i, t});
  };
  for (int i = 0; i < V; ++i) {
    triangle_tree.for_each_overlap(vertex_boxes[i], [&](int t) { vertex_triangle(i, t); });
  }
  shuffle_found(hits);
  sort_id_pairs(hits, V);
  for (const auto& it : hits) {
    const int i = it[0];
    const Tri& tri = m.triangles[it[1]];
    Pair pair;
    pair.p = {i, tri[0], tri[1], tri[2]};
    pair.thickness = thickness;
    pair.friction = friction;
    const Vec3* x[4] = {&(*x0)[i], &(*x0)[tri[0]], &(*x0)[tri[1]], &(*x0)[tri[2]]};
    pair.built_distance = closest_of(pair, x).distance;
    pair.repel = apart_at_rest(pair);
    pairs.push_back(pair);
  }
  // Edge against edge: the pairs (e, f), e < f, by e then f (edges are sorted by their
  // vertex ids, so this is the order of the pairs' vertex ids).
  std::vector<std::array<int, 2>>& near = found_pairs;
  near.clear();
  auto edge_edge = [&](int e, int f) {
    const auto &a = edges[e], &b = edges[f];
    if (a[0] == b[0] || a[0] == b[1] || a[1] == b[0] || a[1] == b[1]) return;
    if (!movable({a[0], a[1], b[0], b[1]})) return;
    Box3 ba = region[a[0]], bb = region[b[0]];
    ba.extend(region[a[1]]);
    bb.extend(region[b[1]]);
    if (box_distance(ba, bb) >= thickness) return;
    near.push_back({std::min(e, f), std::max(e, f)});
  };
  if (edge_tree.empty()) {
    edge_tree.build(edge_boxes, kLeafSize);
  } else {
    edge_tree.refit(edge_boxes);
  }
  edge_tree.for_each_self_overlap(edge_edge);
  shuffle_found(near);
  sort_id_pairs(near, static_cast<int>(edges.size()));
  for (const auto& ef : near) {
    const auto &lo = edges[ef[0]], &hi = edges[ef[1]];
    Pair pair;
    pair.p = {lo[0], lo[1], hi[0], hi[1]};
    pair.edge_edge = true;
    pair.thickness = thickness;
    pair.friction = friction;
    const Vec3* x[4] = {&(*x0)[pair.p[0]], &(*x0)[pair.p[1]], &(*x0)[pair.p[2]], &(*x0)[pair.p[3]]};
    pair.built_distance = closest_of(pair, x).distance;
    pair.repel = apart_at_rest(pair);
    pairs.push_back(pair);
  }
}

// Sorts pairs of ids (a, b), 0 <= a < count, by a, then b: counted into one bucket per
// a, each bucket then sorted (a primitive meets a few dozen others at most).
void ClothContact::Impl::sort_id_pairs(std::vector<std::array<int, 2>>& list, int count) {
  std::vector<int>& first = bucket_first;
  first.assign(count + 1, 0);
  for (const auto& ab : list) ++first[ab[0] + 1];
  for (int a = 0; a < count; ++a) first[a + 1] += first[a];
  std::vector<std::array<int, 2>>& sorted = sorted_pairs;
  sorted.resize(list.size());
  bucket_next.assign(first.begin(), first.end() - 1);
  for (const auto& ab : list) sorted[bucket_next[ab[0]]++] = ab;
  for (int a = 0; a < count; ++a) std::sort(sorted.begin() + first[a], sorted.begin() + first[a + 1]);
  list.swap(sorted);
}

void ClothContact::Impl::add_mesh_pairs(MeshFeatures& f, double thickness) {
  const Model& m = *model;
  const Obstacle& ob = m.obstacles[f.obstacle];
  const ClosedSurface& s = *f.surface;
  const int mesh_index = static_cast<int>(&f - meshes.data());
  const double reach = thickness + f.margin;  // how close a feature may come, m
  // World boxes -> the surface's frame at t = 0 (a box around the turned box).
  const Mat3 to_body = f.rotation0.transpose();
  const Mat3 spread = to_body.cwiseAbs();
  auto body_box = [&](const Box3& world, double pad) {
    const Vec3 centre = ob.center + to_body * (world.center() - f.center0);
    const Vec3 half = spread * (0.5 * world.sizes()) + Vec3::Constant(pad);
    return Box3(centre - half, centre + half);
  };
  auto world_of = [&](int vertex) { return f.center0 + f.rotation0 * (s.vertices()[vertex] - ob.center); };
  auto add = [&](const std::array<int, 4>& p, bool edge_edge, bool repel) {
    Pair pair;
    pair.p = p;
    pair.edge_edge = edge_edge;
    pair.repel = repel && thickness > 0.0;
    pair.obstacle = f.obstacle;
    pair.thickness = thickness;
    pair.friction = ob.friction;
    const Vec3* x[4] = {&start(p[0]), &start(p[1]), &start(p[2]), &start(p[3])};
    pair.built_distance = closest_of(pair, x).distance;
    pairs.push_back(pair);
  };

  // Cloth vertices against the surface's triangles: crossing only (the obstacle query
  // keeps vertices at the thickness).
  for (int i = 0; i < V; ++i) {
    if (m.inv_mass[i] == 0.0) continue;
    s.tree().for_each_overlap(body_box(world_region[i], f.margin), [&](int t) {
      const Tri& tri = s.triangles()[t];
      add({i, kinematic_point(f, mesh_index, tri[0]), kinematic_point(f, mesh_index, tri[1]),
           kinematic_point(f, mesh_index, tri[2])},
          false, false);
    });
  }
  // The surface's vertices against cloth triangles, its edges against cloth edges (those
  // near the cloth). The cloth's
  // trees hold its regions (grown by half its own thickness when self-collision built
  // them); query with the features' boxes grown by the rest.
  std::vector<Box3> tri_boxes(m.triangles.size());
  for (size_t t = 0; t < m.triangles.size(); ++t) {
    const Tri& tri = m.triangles[t];
    Box3 b = world_region[tri[0]];
    b.extend(world_region[tri[1]]);
    b.extend(world_region[tri[2]]);
    tri_boxes[t] = b;
  }
  std::vector<Box3> edge_boxes(edges.size());
  for (size_t e = 0; e < edges.size(); ++e) {
    Box3 b = world_region[edges[e][0]];
    b.extend(world_region[edges[e][1]]);
    edge_boxes[e] = b;
  }
  Bvh cloth_triangles, cloth_edges;
  cloth_triangles.build(tri_boxes);
  cloth_edges.build(edge_boxes);
  const Box3 cloth = cloth_triangles.bounds();
  const Vec3 pad = Vec3::Constant(reach);
  for (int vertex = 0; vertex < static_cast<int>(s.vertices().size()); ++vertex) {
    const Vec3 p = world_of(vertex);
    if (cloth.exteriorDistance(p) > reach) continue;
    cloth_triangles.for_each_overlap(Box3(p - pad, p + pad), [&](int t) {
      const Tri& tri = m.triangles[t];
      add({kinematic_point(f, mesh_index, vertex), tri[0], tri[1], tri[2]}, false, true);
    });
  }
  for (int e = 0; e < static_cast<int>(s.edges().size()); ++e) {
    const auto& edge = s.edges()[e];
    const Vec3 a = world_of(edge[0]), b = world_of(edge[1]);
    Box3 box(a);
    box.extend(b);
    if (box_distance(box, cloth) > reach) continue;
    cloth_edges.for_each_overlap(Box3(box.min() - pad, box.max() + pad), [&](int ce) {
      add({edges[ce][0], edges[ce][1], kinematic_point(f, mesh_index, edge[0]),
           kinematic_point(f, mesh_index, edge[1])},
          true, true);
    });
  }
}

// Pairs that may come within their thickness (or touch) this step: the distance when
// the lists were built, less how far their points have moved since, is a lower bound.
void ClothContact::Impl::select_active() {
  active.clear();
  if (scheduled) {
    // The pairs whose wake value swept + reach may have reached (and those due anyway).
    woken.swap(due);
    due.clear();
    const double threshold = (swept + reach) * (1.0 + 1e-9) + 1e-9;  // m, rounding covered
    const int64_t key = static_cast<int64_t>(std::floor(threshold / quantum));
    if (fresh) {
      woken.resize(watches.size());
      std::iota(woken.begin(), woken.end(), 0);
      fresh = false;
    } else {
      const int64_t last = std::min(key, drained + kBuckets);
      for (int64_t k = drained + 1; k <= last; ++k) {
        std::vector<int>& bucket = buckets[k % kBuckets];
        woken.insert(woken.end(), bucket.begin(), bucket.end());
        bucket.clear();
      }
    }
    drained = std::max(drained, key);
    // Gathered as bits and read out in the order of the lists, as the full pass below gives
    // them (a sort of the woken pairs' order, which the buckets scramble, cost more).
    active_bits.assign((watches.size() + 63) / 64, 0);
    for (int k : woken) {
      double a, b;
      if (!apart(k, &a, &b)) active_bits[k >> 6] |= uint64_t{1} << (k & 63);
      wait(k, a, b);
    }
    for (size_t w = 0; w < active_bits.size(); ++w) {
      for (uint64_t bits = active_bits[w]; bits != 0; bits &= bits - 1) {
        active.push_back(static_cast<int>(64 * w) + __builtin_ctzll(bits));
      }
    }
    start_distance.resize(active.size());
    return;
  }
  // Obstacle vertices move with their obstacle.
  moved_world.resize(V + kinematic_body.size());
  for (size_t k = 0; k < kinematic_body.size(); ++k) moved_world[V + k] = meshes[kinematic_mesh[k]].moved;
  const double* self = moved.data();
  const double* world = moved_world.data();
  for (size_t k = 0; k < watches.size(); ++k) {
    const Watch& w = watches[k];
    const double* m = w.world ? world : self;
    const double a = w.edge_edge ? std::max(m[w.p[0]], m[w.p[1]]) : m[w.p[0]];
    const double b = w.edge_edge ? std::max(m[w.p[2]], m[w.p[3]])
                                 : std::max(m[w.p[1]], std::max(m[w.p[2]], m[w.p[3]]));
    if (w.slack > a + b) continue;
    active.push_back(static_cast<int>(k));
  }
  start_distance.resize(active.size());
}

// Whether a cloth pair cannot come within its thickness (or touch) this step, the test
// of select_active; a and b receive how far its sides have moved since the build, m.
bool ClothContact::Impl::apart(int pair, double* a, double* b) const {
  const Watch& w = watches[pair];
  const double* m = moved.data();
  *a = w.edge_edge ? std::max(m[w.p[0]], m[w.p[1]]) : m[w.p[0]];
  *b = w.edge_edge ? std::max(m[w.p[2]], m[w.p[3]])
                   : std::max(m[w.p[1]], std::max(m[w.p[2]], m[w.p[3]]));
  return w.slack > *a + *b;
}

// Files a pair looked at in this step under its wake value (see `scheduled`).
void ClothContact::Impl::wait(int pair, double a, double b) {
  const double left = static_cast<double>(watches[pair].slack) - (a + b);  // m
  if (!(left > 0.0)) {
    due.push_back(pair);
    return;
  }
  const double key = std::floor((swept + 0.5 * left) / quantum);
  if (!(key > static_cast<double>(drained))) {
    due.push_back(pair);
    return;
  }
  // Never farther than the ring holds (an earlier look is always safe).
  const int64_t k = std::min(static_cast<int64_t>(key), drained + kBuckets - 1);
  buckets[k % kBuckets].push_back(pair);
}

// The vertices of the active pairs (`touched`: the only ones the stage moves), and those
// of them that rest on an obstacle at the end of the step (closer than its thickness plus
// a tenth of the largest pair thickness, or a micrometre).
void ClothContact::Impl::find_supports(double t1) {
  for (int i : touched) support_of[i] = -1;
  touched.clear();
  supports.clear();
  for (int a : active) {
    for (int id : pairs[a].p) {
      if (id < V && support_of[id] == -1) {
        support_of[id] = -2;  // seen
        touched.push_back(id);
      }
    }
  }
  if (model->obstacles.empty()) {
    for (int i : touched) support_of[i] = -1;
    return;
  }
  double band = 1e-6;
  for (int a : active) band = std::max(band, 0.1 * pairs[a].thickness);
  for (int i : touched) {
    support_of[i] = -1;
    if (model->inv_mass[i] == 0.0) continue;
    const Vec3& p = (*x1)[i];
    for (const Obstacle& ob : model->obstacles) {
      const Vec3 centre = ob.center_at(t1);
      const Mat3 turn = ob.rotation(t1);
      Vec3 n;
      const double reach = ob.thickness + band;
      const double d = ob.signed_distance_from(p, centre, &n, turn, reach);
      if (d >= reach) continue;
      support_of[i] = static_cast<int>(supports.size());
      supports.push_back({n, n.dot(p), ob.point_velocity(p, t1)});
      break;
    }
  }
}

// The distance of every active pair at x0, m.
void ClothContact::Impl::measure_start() {
  start_distance.resize(active.size());
  for (size_t a = 0; a < active.size(); ++a) {
    const Pair& pair = pairs[active[a]];
    const Vec3* x[4] = {&start(pair.p[0]), &start(pair.p[1]), &start(pair.p[2]), &start(pair.p[3])};
    start_distance[a] = closest_of(pair, x).distance;
  }
}

// Step 1: repulsion and friction between pairs near each other at x0.
void ClothContact::Impl::proximity(ContactStats& stats) {
  for (size_t a = 0; a < active.size(); ++a) {
    const Pair& pair = pairs[active[a]];
    const Vec3* x[4] = {&start(pair.p[0]), &start(pair.p[1]), &start(pair.p[2]), &start(pair.p[3])};
    const Closest c = closest_of(pair, x);
    start_distance[a] = c.distance;
    if (!pair.repel || c.distance <= 1e-12) continue;
    // Two cloth edges closest at an end of one: that end is at most as far from a triangle
    // of the other edge, whose vertex-triangle pair repels it (unless the two are
    // neighbours in the fabric), so this pair is left out: on layers at rest most edge
    // pairs meet end to end, and each repeated that impulse.
    if (pair.edge_edge && pair.obstacle < 0 && at_an_end(c)) continue;
    // How close the pair may come by the end of the step: at most to the thickness, and
    // if already closer, a tenth of the way back out.
    const double shortfall = pair.thickness - c.distance;
    Vec3 n = c.gap / c.distance;
    if (pair.obstacle >= 0) {
      // An obstacle's feature: the integrator keeps the cloth's vertices at the thickness
      // from its surface, and this pushes the cloth between them out along the surface's
      // normal, only once within the thickness. Cloth sliding over a moving obstacle near
      // its feature is then no approach, which the closest points' direction, leaning
      // along the surface, would make it (docs/implicit.md, "A moving mesh obstacle").
      if (shortfall <= 0.0) continue;
      // gap runs from the second primitive to the first: toward the obstacle's vertex
      // (vertex-triangle pairs), away from the obstacle's edge (edge-edge pairs).
      const Vec3 out = obstacle_normal(pair);
      n = pair.edge_edge ? out : Vec3(-out);
    }
    Vec3 relative = Vec3::Zero();
    for (int k = 0; k < 4; ++k) {
      if (pair.p[k] < V) {
        relative += c.weights[k] * (*v)[pair.p[k]];
      } else {
        relative += c.weights[k] * (k1[pair.p[k] - V] - k0[pair.p[k] - V]) / dt;
      }
    }
    const double vn = relative.dot(n);
    const double target = shortfall > 0.0 ? kRepulsion * shortfall / dt : shortfall / dt;
    if (vn >= target) continue;
    const double w = effective_inverse_mass(pair.p, c.weights);
    if (w == 0.0) continue;
    ++stats.proximities;
    const double dvn = target - vn;  // change of the relative normal velocity
    Vec3 tangential = relative - vn * n;
    const double vt = tangential.norm();
    Vec3 change = dvn * n;
    if (pair.friction > 0.0 && vt > 0.0) {
      change -= std::min(vt, pair.friction * dvn) * (tangential / vt);
    }
    for (int k = 0; k < 4; ++k) kick(pair.p[k], (c.weights[k] * inv_mass(pair.p[k]) / w) * change);
  }
}

// How far point id moves over the step, |x1 - x0| (m), measured once in detection round
// `round` for all the pairs that share it.
double ClothContact::Impl::motion_in_round(int id, int round) {
  if (id >= V) return (end(id) - start(id)).norm();
  if (motion_round[id] != round) {
    motion_round[id] = round;
    motion_of[id] = (end(id) - start(id)).norm();
  }
  return motion_of[id];
}

// Step 2: continuous detection over x0 -> x1 of the active pairs; each impact becomes a
// constraint. Returns how many were found.
int ClothContact::Impl::detect(std::vector<Constraint>& found) {
  found.clear();
  const int since = detection++;
  const bool full = full_detection;
  full_detection = false;
  for (size_t a = 0; a < active.size(); ++a) {
    const Pair& pair = pairs[active[a]];
    if (!full) {
      bool moved_since = false;
      for (int id : pair.p) moved_since = moved_since || (id < V && changed_at[id] >= since);
      if (!moved_since) continue;
    }
    double motion[4];
    for (int k = 0; k < 4; ++k) motion[k] = motion_in_round(pair.p[k], since);
    const double approach = pair.edge_edge
                                ? std::max(motion[0], motion[1]) + std::max(motion[2], motion[3])
                                : motion[0] + std::max({motion[1], motion[2], motion[3]});
    if (start_distance[a] - approach > kTouch) continue;
    // A vertex that starts on an obstacle's surface (where its response put it) slides
    // along it: only a vertex that starts clear of it can pass through.
    if (pair.obstacle >= 0 && !pair.edge_edge && !pair.repel && start_distance[a] < kClear) {
      continue;
    }
    const Vec3 s[4] = {start(pair.p[0]), start(pair.p[1]), start(pair.p[2]), start(pair.p[3])};
    const Vec3 e[4] = {end(pair.p[0]), end(pair.p[1]), end(pair.p[2]), end(pair.p[3])};
    const std::optional<Impact> impact =
        pair.edge_edge ? edge_edge_impact(s, e, kTouch) : vertex_triangle_impact(s, e, kTouch);
    if (!impact) continue;
    // An obstacle's triangle is passed through only from outside (its front): a vertex
    // behind its plane came over a neighbouring facet, not through this one.
    if (pair.obstacle >= 0 && !pair.edge_edge && !pair.repel &&
        impact->normal.dot((s[2] - s[1]).cross(s[3] - s[1])) <= 0.0) {
      continue;
    }
    Constraint c;
    c.p = pair.p;
    for (int k = 0; k < 4; ++k) c.weights[k] = impact->weights[k];
    c.normal = impact->normal;
    c.separation = std::max(1e-6, 0.1 * pair.thickness);
    if (effective_inverse_mass(c.p, c.weights) == 0.0) continue;
    found.push_back(c);
  }
  return static_cast<int>(found.size());
}

// An inelastic impulse along the impact's normal that leaves the pair its separation
// apart at the end of the step.
void ClothContact::Impl::push_apart(const Constraint& c) {
  double gap = 0.0;
  for (int k = 0; k < 4; ++k) gap += c.weights[k] * c.normal.dot(end(c.p[k]));
  if (gap >= c.separation) return;
  const double w = effective_inverse_mass(c.p, c.weights);
  const double correction = (c.separation - gap) / w;  // m, per unit inverse mass
  for (int k = 0; k < 4; ++k) {
    kick(c.p[k], (c.weights[k] * inv_mass(c.p[k]) * correction / dt) * c.normal);
  }
}

// Step 3: all constraints met together (projected Gauss-Seidel on the end positions, the
// mass-weighted nearest motion: Harmon et al. 2008), with the obstacles that support
// zone vertices as constraints of their own. True when they all hold; when they do not,
// or when meeting them would move a vertex farther than the step could (a pinch that no
// motion resolves), the end positions are left as they were and false is returned.
bool ClothContact::Impl::solve_zones() {
  std::vector<int> members;
  for (const Constraint& c : constraints) {
    for (int id : c.p) {
      if (id < V) members.push_back(id);
    }
  }
  std::sort(members.begin(), members.end());
  members.erase(std::unique(members.begin(), members.end()), members.end());
  std::vector<Constraint> all = constraints;
  double limit = 0.0;
  Vec3List saved_x(members.size()), saved_v(members.size());
  for (size_t k = 0; k < members.size(); ++k) {
    const int i = members[k];
    saved_x[k] = (*x1)[i];
    saved_v[k] = (*v)[i];
    limit = std::max(limit, ((*x1)[i] - (*x0)[i]).norm());
    const int s = support_of[i];
    if (s < 0) continue;
    Constraint held;
    held.p = {i, i, i, i};
    held.weights[0] = 1.0;
    held.weights[1] = held.weights[2] = held.weights[3] = 0.0;
    held.normal = supports[s].normal;
    held.separation = supports[s].offset;
    all.push_back(held);
  }
  double thickest = 0.0;
  for (const Constraint& c : constraints) thickest = std::max(thickest, c.separation);
  limit = 2.0 * limit + 100.0 * thickest + 1e-4;
  project_supports = false;
  bool converged = false;
  for (int sweep = 0; sweep < kZoneSweeps && !converged; ++sweep) {
    double worst = 0.0;
    for (Constraint& c : all) {
      double gap = 0.0;
      for (int k = 0; k < 4; ++k) gap += c.weights[k] * c.normal.dot(end(c.p[k]));
      const double w = effective_inverse_mass(c.p, c.weights);
      double step = (c.separation - gap) / w;  // positive pushes apart
      step = std::max(step, -c.lambda);         // the accumulated correction stays >= 0
      if (step == 0.0) continue;
      c.lambda += step;
      worst = std::max(worst, std::fabs(step * w));
      for (int k = 0; k < 4; ++k) kick(c.p[k], (c.weights[k] * inv_mass(c.p[k]) * step / dt) * c.normal);
    }
    converged = worst <= 1e-9;
  }
  project_supports = true;
  bool reasonable = true;
  for (size_t k = 0; k < members.size(); ++k) {
    reasonable = reasonable && ((*x1)[members[k]] - saved_x[k]).norm() <= limit;
  }
  if (converged && reasonable) {
    for (size_t k = 0; k < constraints.size(); ++k) constraints[k].lambda = all[k].lambda;
    return true;
  }
  for (size_t k = 0; k < members.size(); ++k) {
    (*x1)[members[k]] = saved_x[k];
    (*v)[members[k]] = saved_v[k];
    changed_at[members[k]] = detection;
  }
  return false;
}

// Moves a zone rigidly: with the obstacle it touches (mesh_index >= 0), else with the
// zone's own momentum and angular momentum about its centre of mass (Provot 1997).
void ClothContact::Impl::move_rigidly(const std::vector<int>& zone, int mesh_index) {
  if (mesh_index >= 0) {
    const MeshFeatures& f = meshes[mesh_index];
    for (int i : zone) {
      if (model->inv_mass[i] == 0.0) continue;
      const Vec3 local = f.rotation0.transpose() * ((*x0)[i] - f.center0);
      const Vec3 target = f.center1 + f.rotation1 * local;
      (*x1)[i] = target;
      (*v)[i] = (target - (*x0)[i]) / dt;
      changed_at[i] = detection;
    }
    return;
  }
  // A zone holding a pinned vertex cannot move as a whole: it stays where it started.
  for (int i : zone) {
    if (model->inv_mass[i] != 0.0) continue;
    for (int j : zone) {
      if (model->inv_mass[j] == 0.0) continue;
      (*x1)[j] = (*x0)[j];
      (*v)[j].setZero();
      changed_at[j] = detection;
    }
    return;
  }
  double mass = 0.0;
  Vec3 centre = Vec3::Zero(), momentum = Vec3::Zero();
  for (int i : zone) {
    mass += model->mass[i];
    centre += model->mass[i] * (*x0)[i];
    momentum += model->mass[i] * (*v)[i];
  }
  centre /= mass;
  const Vec3 velocity = momentum / mass;
  Vec3 angular = Vec3::Zero();
  Mat3 inertia = Mat3::Zero();
  for (int i : zone) {
    const Vec3 r = (*x0)[i] - centre;
    angular += model->mass[i] * r.cross((*v)[i] - velocity);
    inertia += model->mass[i] * (r.squaredNorm() * Mat3::Identity() - r * r.transpose());
  }
  const Vec3 omega = inertia.determinant() > 1e-30 ? Vec3(inertia.ldlt().solve(angular)) : Vec3::Zero();
  const double angle = omega.norm() * dt;
  const Mat3 turn = angle > 0.0 ? Eigen::AngleAxisd(angle, omega.normalized()).toRotationMatrix()
                                : Mat3::Identity();
  for (int i : zone) {
    (*x1)[i] = centre + velocity * dt + turn * ((*x0)[i] - centre);
    (*v)[i] = ((*x1)[i] - (*x0)[i]) / dt;
    changed_at[i] = detection;
  }
}

ContactStats ClothContact::Impl::resolve(double t0) {
  ContactStats stats;
  // The same step again (cloth pairs only): its start is where the frame had the offset of
  // the last call, and the lists built then still hold while the new end stays in them.
  if (t0 == last_t0 && dt == last_dt && meshes.empty()) frame_start = last_frame_start;
  place_meshes(t0, t0 + dt);
  stats.calls = 1;
  if (!lists_valid()) {
    rebuild();
    stats.rebuilt = true;
    ++stats.builds;
    stats.build_distances += static_cast<int64_t>(pairs.size());
  }
  stats.candidates = static_cast<int>(pairs.size());
  support_of.resize(V, -1);
  changed_at.resize(V, -1);
  select_active();
  find_supports(t0 + dt);
  proximity(stats);
  collide(stats);
  // The stage's own impulses may have carried a vertex out of its region, where the lists
  // could miss a pair: then they are rebuilt around the new end positions and checked
  // again.
  for (int again = 0; again < 2 && !ends_in_regions(); ++again) {
    rebuild();
    stats.rebuilt = true;
    ++stats.builds;
    stats.build_distances += static_cast<int64_t>(pairs.size());
    stats.candidates = static_cast<int>(pairs.size());
    select_active();
    find_supports(t0 + dt);
    measure_start();
    collide(stats);
  }
  last_t0 = t0;
  last_dt = dt;
  last_frame_start = frame_start;
  frame_start = frame_end;
  return stats;
}

// Steps 2 and 3: continuous detection, impulses, impact zones, rigid zones.
void ClothContact::Impl::collide(ContactStats& stats) {
  if (active.empty()) return;
  full_detection = true;
  changed_at.resize(V, -1);
  motion_of.resize(V);
  motion_round.resize(V, -1);
  std::vector<Constraint> found;
  constraints.clear();
  // Plain impulses first.
  for (int round = 0; round < kImpulseRounds; ++round) {
    ++stats.rounds;
    if (detect(found) == 0) return;
    stats.impacts += static_cast<int>(found.size());
    for (const Constraint& c : found) push_apart(c);
    constraints.insert(constraints.end(), found.begin(), found.end());
  }
  // Impact zones: every impact so far (and each new one) constrains the end positions.
  for (Constraint& c : constraints) c.lambda = 0.0;
  for (int round = 0; round < kZoneRounds; ++round) {
    if (!solve_zones()) break;  // the rigid zones below take over
    ++stats.rounds;
    if (detect(found) == 0) {
      zones.reset(V);
      for (const Constraint& c : constraints) {
        int first = -1;
        for (int k = 0; k < 4; ++k) {
          if (c.p[k] >= V) continue;
          if (first < 0) first = c.p[k];
          zones.join(first, c.p[k]);
        }
      }
      std::vector<char> root(V, 0);
      for (const Constraint& c : constraints) {
        for (int k = 0; k < 4; ++k) {
          if (c.p[k] < V) root[zones.find(c.p[k])] = 1;
        }
      }
      stats.zones = static_cast<int>(std::count(root.begin(), root.end(), 1));
      return;
    }
    stats.impacts += static_cast<int>(found.size());
    constraints.insert(constraints.end(), found.begin(), found.end());
  }
  // Last resort: the zones of the impacts left move rigidly; zones grow while impacts
  // remain, and a zone that still collides is held at its start (or carried by its
  // obstacle), where nothing crosses.
  zones.reset(V);
  std::vector<int> zone_mesh(V, -1);
  auto absorb = [&](const std::vector<Constraint>& list) {
    for (const Constraint& c : list) {
      int first = -1, mesh = -1;
      for (int k = 0; k < 4; ++k) {
        if (c.p[k] >= V) {
          mesh = kinematic_mesh[c.p[k] - V];
          continue;
        }
        if (first < 0) first = c.p[k];
        zones.join(first, c.p[k]);
      }
      if (first >= 0 && mesh >= 0) zone_mesh[first] = mesh;
    }
  };
  absorb(constraints);
  for (int round = 0; round <= kRigidRounds; ++round) {
    if (detect(found) == 0) return;
    ++stats.rounds;
    stats.impacts += static_cast<int>(found.size());
    absorb(found);
    // Collect zones touched by the impacts left.
    std::vector<int> members_root(V, -1);
    std::vector<std::vector<int>> groups;
    std::vector<int> group_mesh;
    std::vector<char> hit(V, 0);
    for (const Constraint& c : found) {
      for (int k = 0; k < 4; ++k) {
        if (c.p[k] < V) hit[zones.find(c.p[k])] = 1;
      }
    }
    std::vector<int> group_of(V, -1);
    for (int i = 0; i < V; ++i) {
      const int r = zones.find(i);
      if (!hit[r]) continue;
      if (group_of[r] < 0) {
        group_of[r] = static_cast<int>(groups.size());
        groups.emplace_back();
        group_mesh.push_back(-1);
      }
      groups[group_of[r]].push_back(i);
      if (zone_mesh[i] >= 0) group_mesh[group_of[r]] = zone_mesh[i];
    }
    for (size_t g = 0; g < groups.size(); ++g) {
      if (round < kRigidRounds) {
        move_rigidly(groups[g], group_mesh[g]);
      } else {
        for (int i : groups[g]) {  // held at the start: nothing crosses there
          if (group_mesh[g] >= 0) {
            move_rigidly({i}, group_mesh[g]);
          } else {
            (*x1)[i] = (*x0)[i];
            (*v)[i].setZero();
            changed_at[i] = detection;
          }
        }
      }
    }
    stats.rigid_zones += static_cast<int>(groups.size());
  }
  stats.unresolved = detect(found);
  return;
}

ClothContact::ClothContact() : impl_(std::make_unique<Impl>()) {}
void ClothContact::shuffle_broad_phase(uint64_t seed) { impl_->shuffle_seed = seed; }
ClothContact::~ClothContact() = default;

ContactStats ClothContact::resolve(const Model& model, double t0, double dt, const Vec3List& x0,
                                   Vec3List& x1, Vec3List& v) {
  Impl& s = *impl_;
  s.model = &model;
  s.dt = dt;
  s.x0 = &x0;
  s.x1 = &x1;
  s.v = &v;
  s.prepare_topology(model);
  return s.resolve(t0);
}

}  // namespace tissu
