// The per-vertex part of an explicit step in one vectorised pass over a vertex
// block (Google Highway, the instruction set chosen at run time as
// membrane_simd.h): the sum of the triangle chunks' buffers, gravity, air
// damping (eq. 7), the integrator's update (eq. 9, eq. 10 or the paper's
// printed scheme) and the divergence check's per-vertex work. Every vertex gets
// the scalar stages' operations in their order, without fused multiply-adds, so
// positions, velocities and the check's findings are the same bits as
// forces_stage2 + the scalar integration + the scalar check, on any vector
// width.
#pragma once

#include "core/types.h"
#include "physics/force_plan.h"
#include "physics/model.h"
#include "physics/step_scratch.h"

namespace tissu {

// For the vertices of block `block` of `plan` (stage 1 done: chunk buffers
// filled, and f holding the bending forces when the model has bending): forces
// (N) = bending + chunk buffers in chunk order + gravity + air damping, then v
// (m/s) and x (m) updated by the model's explicit integrator with step model.dt
// (s). With `check`, records the first non-finite vertex and the first fastest
// one as the scalar check does. f's entries of the block are left undefined
// (the last block's may hold forces). The model's integrator must be explicit.
void finish_block_simd(const Model &model, const ForcePlan &plan, int block,
                       Vec3List &f, Vec3List &x, Vec3List &v,
                       BlockCheck *check);

// The divergence check of vertices [first, end) with positions x (m) and
// velocities v (m/s), vectorised: the findings of check_vertex on each vertex
// in order. For blocks whose vertices the obstacles moved after the pass.
void check_block_simd(const Vec3List &x, const Vec3List &v, int first, int end,
                      BlockCheck &check);

} // namespace tissu
