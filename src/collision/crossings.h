// Exact check that triangle meshes do not cross: every intersecting pair of triangles is
// found with exact predicates (CGAL's Exact_predicates_inexact_constructions_kernel), so a
// reported pair truly intersects and no intersecting pair is missed. Triangles that share
// vertices (neighbours in a mesh) count as crossing only where they meet beyond what they
// share: a shared edge with the two triangles folded flat onto each other, or a shared
// vertex with more than that vertex in common. Touching counts as crossing.
// Tested in tests/collision/crossings_test; backs `tissu run --check`.
#pragma once

#include <cstddef>
#include <limits>
#include <vector>

#include "core/types.h"

namespace tissu {

struct TrianglePair {
  int first = -1;   // triangle id in the first mesh
  int second = -1;  // triangle id in the second mesh (the same mesh for self-crossings)
};

struct CrossingReport {
  std::size_t count = 0;             // intersecting pairs found (at most the limit)
  std::vector<TrianglePair> pairs;   // the first of them, in a deterministic order
  bool any() const { return count > 0; }
};

// Intersecting pairs of triangles of one mesh. Stops after `limit` pairs.
CrossingReport self_crossings(const Vec3List& x, const TriList& triangles,
                              std::size_t limit = std::numeric_limits<std::size_t>::max());

// Intersecting pairs between two meshes (no vertex is shared between them).
CrossingReport crossings_between(const Vec3List& xa, const TriList& ta, const Vec3List& xb,
                                 const TriList& tb,
                                 std::size_t limit = std::numeric_limits<std::size_t>::max());

}  // namespace tissu
