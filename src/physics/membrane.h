// First-order finite-element membrane of Volino et al. 2009 as written in the paper
// (eq. 3-6): Green strain from U = dP/du, V = dP/dv, stress = E strain, and the vertex
// forces F_j = -A (s_uu r_uj U + s_vv r_vj V + s_uv (r_uj V + r_vj U)), which are exactly
// minus the gradient of the triangle energy W = A/2 e^T E e.
// Optional strain-rate damping adds the viscous stress tau * E * de/dt.
// Biphasic response (Material::compression_ratio kappa < 1, physics/biphasic.h): a woven
// fabric's yarns buckle under axial compression, so the weft and warp strains enter the
// energy through a smooth map whose slope falls from 1 to sqrt(kappa) in compression:
// W = A/2 e~^T E e~, and the compressive stiffness tends to kappa times the tensile one.
// Only the scalar kernel has it.
#pragma once

#include <vector>

#include "core/types.h"
#include "physics/force_term.h"
#include "physics/model.h"

namespace tissu {

// Green strain (e_uu, e_vv, e_uv) of one triangle (eq. 3-4); e_uv = U.V.
Vec3 triangle_strain(const TriangleRest& rest, const Vec3& a, const Vec3& b, const Vec3& c);

// Energy of one triangle, J, with the compression ratio kappa (1: linear).
double triangle_energy(const TriangleRest& rest, const Mat3& E, const Vec3& a, const Vec3& b,
                       const Vec3& c, double compression_ratio = 1.0);

// Forces on the three corners of one triangle (eq. 6), N, with the compression ratio.
void triangle_forces(const TriangleRest& rest, const Mat3& E, const Vec3 x[3], Vec3 f[3],
                     double compression_ratio = 1.0);

// Adds the membrane forces of triangles [first, end) (and their strain-rate damping forces
// when the material has damping and `v` is given), N: with the vectorised kernel
// (membrane_simd.h) when the model has its layout, else the scalar one. Both give the
// same bits. A material with a compression ratio below 1 always takes the scalar kernel.
void add_membrane_forces(const Model& model, const Vec3List& x, const Vec3List* v, int first,
                         int end, VertexForces out);
// The same with the scalar kernel, one triangle after the other: the reference.
void add_membrane_forces_scalar(const Model& model, const Vec3List& x, const Vec3List* v,
                                int first, int end, VertexForces out);

// Total membrane energy, J.
double membrane_energy(const Model& model, const Vec3List& x);

// The energy of every triangle at x (T values), J.
void triangle_energies(const Model& model, const Vec3List& x, std::vector<double>& energies);

// The change of the membrane energy from the state whose triangle energies are `before`
// to x, J, summed triangle by triangle (accurate where the change is small next to the
// total).
double membrane_energy_change(const Model& model, const Vec3List& x,
                              const std::vector<double>& before);

// Largest principal Green strain over all triangles (dimensionless).
double max_principal_strain(const Model& model, const Vec3List& x);

// Adds the Jacobian of triangles [first, end): c_x df/dx (N/m) and c_v df/dv (N*s/m, the
// damping's). With `project_psd` the stress (geometric) term uses the nearest positive
// semi-definite 2x2 stress, so -df/dx is positive semi-definite (for Newton/CG solves).
// With damping and velocities `v`, df/dx also carries the damping force's dependence on x:
// the viscous stress joins the stress term, and without `project_psd` the (non-symmetric)
// term -tau A J_i E dJ_j^T/dt is added too (dropped when projecting).
void add_membrane_jacobian(const Model& model, const Vec3List& x, const Vec3List* v,
                           bool project_psd, int first, int end, JacobianSink& sink);

}  // namespace tissu
