// The bending forces of bending.h, f_i -= sum_j Q_ij xc_j (xc = x - origin), with the three
// coordinates of a vertex in one vector (Google Highway, AVX2 or AVX-512 chosen at run
// time; narrower instruction sets run the scalar loop). Each row's sum keeps the scalar
// loop's order and nothing is fused into FMA, so the bits are the scalar loop's.
#pragma once

#include "physics/bending.h"
#include "physics/force_term.h"

namespace tissu {

// xc = x - origin, as center_positions (bending.h), one vector per vertex.
void center_positions_simd(const Vec3List& x, const Vec3& origin, CenteredPositions& xc);

// f_i -= sum_j Q_ij xc_j for vertices [first, end), N.
void add_bending_forces_simd(const BendingModel& model, const CenteredPositions& xc, int first,
                             int end, VertexForces out);

}  // namespace tissu
