// The vectorised near-test of the collision stage (Google Highway, the instruction set
// chosen at run time as membrane_simd.h): which vertices of a block may be closer to a
// sphere, cylinder or plane than its thickness. Almost every vertex is far from every
// obstacle; the exact scalar response (collide_vertex) then runs on the few selected.
#pragma once

#include <vector>

#include "core/types.h"
#include "physics/obstacle.h"

namespace tissu {

// Writes to `selected` (room for end - first) the indices, ascending, of the vertices of
// [first, end) of x (m) that may be closer to one of the placed obstacles than its
// thickness, and returns how many. Conservative: every vertex collide_vertex would move
// is selected; a vertex within a relative 1e-12 of the thickness (far more than the
// rounding of either distance computation) is selected too, as is a non-finite one, the
// tail of fewer than a vector's lanes, and every vertex when a mesh obstacle is placed
// (meshes are answered by their own grid and tree, scalar).
int select_near_obstacles(const std::vector<PlacedObstacle>& placed, const Vec3List& x,
                          int first, int end, int* selected);

}  // namespace tissu
