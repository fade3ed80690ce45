// The points of a disk meshed finer in a band (generate.h, generate_disk with a
// DiskGrading): concentric rings spaced by the local target edge, each turned by a random
// angle. Arguments are checked by the caller.
#pragma once

#include <cstdint>

#include "core/types.h"
#include "mesh/generate.h"

namespace tissu {

// Target edge (m) at distance r (m) from the centre: `coarse` outside the band, `coarse *
// fine_ratio` inside it, linear in r across the transitions on either side.
double graded_edge(const DiskGrading& g, double coarse, double r);

// Ring points: the centre, rings at `inner_radius` and `radius` (exact circles), rings in
// between spaced by sqrt(3)/2 of the local edge and holding 2 pi r / edge points each.
// The coarse edge is chosen so that their Delaunay triangulation has about `triangles`.
Vec2List graded_disk_points(double radius, int triangles, uint64_t seed, double inner_radius,
                            const DiskGrading& grading);

}  // namespace tissu
