// The per-vertex part of an explicit step, one vertex block at a time: finish
// the forces (force_plan.h, stage 2), integrate, check for divergence.
// finish_block_simd (vertex_pass_simd.h) does it in one vectorised pass; the
// functions here are the scalar stages it reproduces bit for bit
// (tests/physics/vertex_pass_simd_test).
#pragma once

#include "core/types.h"
#include "physics/force_plan.h"
#include "physics/model.h"
#include "physics/step_scratch.h"

namespace tissu {

// Eq. 9 (explicit Euler), eq. 10 (modified / symplectic Euler) and the paper's
// "calcul_vitesse_position" as printed (V += h F / (2 m), P += h V) for
// vertices [first, end): forces f (N), positions x (m), velocities v (m/s),
// step model.dt (s). Other integrators: nothing.
void integrate_vertices(const Model &model, int first, int end,
                        const Vec3List &f, Vec3List &x, Vec3List &v);

// The divergence check of vertex i: the first non-finite vertex, else the first
// of the fastest (squared speed, m^2/s^2).
void check_vertex(int i, const Vec3 &x, const Vec3 &v, BlockCheck &check);

// The scalar stages one after the other for vertex block `block`: forces_stage2
// into f, integrate_vertices, and with `check` check_vertex for each vertex.
void finish_block_scalar(const Model &model, const ForcePlan &plan, int block,
                         Vec3List &f, Vec3List &x, Vec3List &v,
                         BlockCheck *check);

} // namespace tissu
