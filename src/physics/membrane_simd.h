// The membrane forces of membrane.h vectorised over triangles (Google Highway, the best
// instruction set of the processor chosen at run time: AVX-512, AVX2, SSE4, ...).
// Lane l of each vector computes triangle t + l with the same operations in the same
// order as the scalar kernel, without fused multiply-adds, and the corner forces are added
// to the vertices triangle by triangle in order: the result is the same bits as the
// scalar kernel's on any vector width (docs/physics.md).
#pragma once

#include "physics/force_term.h"
#include "physics/membrane_layout.h"
#include "physics/model.h"

namespace tissu {

// Adds the membrane forces of triangles [first, end) (with strain-rate damping when the
// material has it and `v` is given), N. `layout` must be the model's (same mesh_id).
void add_membrane_forces_simd(const Model& model, const MembraneLayout& layout,
                              const Vec3List& x, const Vec3List* v, int first, int end,
                              VertexForces out);

// The instruction set the kernel runs on in this process ("AVX3", "AVX2", ...).
const char* membrane_simd_target();

}  // namespace tissu
