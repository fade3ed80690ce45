// A closed, consistently oriented triangle surface (the boundary of a solid) with exact
// signed distance queries: the closest point by a bounding-volume hierarchy, the sign by
// angle-weighted pseudo-normals (Baerentzen & Aanaes 2005, exact for closed manifold
// surfaces that do not cross themselves), and a coarse grid of signed distances that
// answers points far from the surface in constant time. Lengths in m, in the surface's
// own frame. Tested in tests/collision/closed_surface_test.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "collision/bvh.h"
#include "collision/crossings.h"
#include "collision/wide_bvh.h"
#include "core/types.h"

namespace tissu {

// The point of a surface closest to a query point.
struct SurfaceQuery {
  double distance = 0.0;        // signed distance, m (negative inside); see closest_within
  Vec3 point = Vec3::Zero();    // closest surface point, m
  Vec3 normal = Vec3::UnitZ();  // outward unit normal: the direction in which the distance
                                // grows (the pseudo-normal on the surface itself)
  int triangle = -1;            // triangle holding the closest point; -1 when far
};

class ClosedSurface {
 public:
  // Checks and prepares a surface. `places` names each triangle for messages (e.g. "face
  // 12"; empty: "triangle <id>"). Throws InputError "<source>: <problem>" (one line) for:
  // no triangles, a vertex id out of range or repeated in a triangle, a non-finite vertex,
  // a triangle of zero area, an edge bordered by one triangle (not closed) or by more than
  // two (non-manifold), two triangles ordered against each other across an edge, and a
  // vertex where separate fans of triangles meet (non-manifold). A surface whose
  // triangles all face inward (negative enclosed volume) is reversed; reversed() says so.
  // A surface that crosses itself (parts pushed into each other, as in many scanned and
  // modelled bodies) is accepted, and self_crossings() reports where: the distance stays
  // exact and its sign right outside the solid and near its outer surface, but inside,
  // near a crossing, a point can be taken for outside (its closest triangle is then one
  // of the hidden ones).
  ClosedSurface(Vec3List vertices, TriList triangles, const std::string& source,
                const std::vector<std::string>& places = {});

  // Exact signed distance from p to the surface and the closest point. `hint`: a triangle
  // expected to be near (the answer for a nearby point, such as the same vertex a step
  // before), or -1; a good hint makes the search several times cheaper, any hint gives
  // the same answer.
  SurfaceQuery closest(const Vec3& p, int hint = -1) const;
  // The same where it matters: exact when |distance| < reach; farther points may get
  // only a bound, with the right sign and |distance| >= reach (triangle = -1). Points far
  // from the surface cost a grid lookup instead of a tree search.
  SurfaceQuery closest_within(const Vec3& p, double reach, int hint = -1) const;

  const Vec3List& vertices() const { return vertices_; }
  const TriList& triangles() const { return triangles_; }
  const std::vector<std::array<int, 2>>& edges() const { return edges_; }  // (E) vertex ids
  const std::vector<std::array<int, 3>>& triangle_edges() const { return triangle_edges_; }
  const Vec3List& face_normals() const { return face_normals_; }  // (T) unit
  // (V) angle-weighted pseudo-normals, outward, not of unit length.
  const Vec3List& vertex_normals() const { return vertex_normals_; }
  // Edges whose two triangles meet at a convex angle with normals more than kSharpAngle
  // apart (a table's edges, not a body's gentle curves).
  const std::vector<int>& sharp_edges() const { return sharp_edges_; }
  const Bvh& tree() const { return tree_; }
  const Box3& bounds() const { return tree_.bounds(); }
  bool reversed() const { return reversed_; }
  const CrossingReport& self_crossings() const { return self_crossings_; }  // exact check
  double volume() const { return volume_; }  // m^3, enclosed

  static constexpr double kSharpAngle = 20.0 * 3.14159265358979323846 / 180.0;  // rad

 private:
  void check_topology(const std::string& source, const std::vector<std::string>& places);
  void compute_normals();
  void build_far_grid();
  SurfaceQuery closest_bounded(const Vec3& p, double max_distance2, int hint) const;
  double distance2_to(int triangle, const Vec3& p) const;

  Vec3List vertices_;
  TriList triangles_;
  std::vector<std::array<int, 2>> edges_;
  std::vector<std::array<int, 3>> triangle_edges_;  // (T) edge ids of ab, bc, ca
  Vec3List face_normals_;
  Vec3List edge_normals_;    // (E) pseudo-normals: sum of the two face normals
  Vec3List vertex_normals_;  // (V) angle-weighted pseudo-normals
  std::vector<int> sharp_edges_;
  Bvh tree_;
  WideBvh wide_{Bvh()};  // tree_ collapsed for closest-point queries
  bool reversed_ = false;
  double volume_ = 0.0;
  CrossingReport self_crossings_;

  // Far-field grid: signed distance at each cell centre over the bounds grown by a margin.
  Vec3 grid_origin_ = Vec3::Zero();  // m, corner of cell (0, 0, 0)
  double cell_ = 1.0;                // m, cell edge
  std::array<int, 3> cells_ = {0, 0, 0};
  std::vector<float> cell_distance_;  // m, at cell centres
};

}  // namespace tissu
