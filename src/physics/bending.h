// Bending of the cloth sheet: a discrete plate energy E = sum over triangles of
// A_T/2 (B_weft |x_uu|^2 + B_warp |x_vv|^2 + (B_weft + B_warp) |x_uv|^2), where x_uu, x_vv,
// x_uv are second derivatives of the 3D position with respect to the rest coordinates
// (u = weft, v = warp), estimated on each triangle by a quadratic patch through the
// triangle and the three vertices across its edges (the apices of its three hinges).
//
// For an isometric deformation of the flat rest sheet (cloth barely stretches) these
// second derivatives are normal to the surface and their norms are the curvatures, so the
// energy is the orthotropic plate energy 1/2 (D11 k_uu^2 + D22 k_vv^2 + 4 D66 k_uv^2) with
// D11 = B_weft, D22 = B_warp, D66 = (B_weft + B_warp)/4: a sheet rolled on a cylinder of
// curvature k has energy B(phi)/2 k^2 per area, B(phi) = B_weft cos^2 phi + B_warp sin^2 phi,
// phi the angle between the direction of curvature and u. This is the "isometric bending"
// idea of Bergou et al. 2006 (quadratic energy, constant Hessian, flat sheet in the kernel)
// with a Hessian operator that is exact for quadratic fields on any triangulation, so the
// energy converges on irregular meshes (dihedral-angle and cotangent hinge energies do not:
// see docs/bending.md).
//
// The energy is a quadratic form, E = 1/2 sum_{c=x,y,z} X_c^T Q X_c with one constant
// symmetric positive semi-definite V x V matrix Q (N/m) whose kernel is exactly the affine
// maps of the rest plane. Forces are -Q x and the force Jacobian is -Q (x) I3, exact,
// constant, symmetric and negative semi-definite.
#pragma once

#include <Eigen/Sparse>
#include <vector>

#include "core/types.h"
#include "physics/block_triplets.h"

namespace tissu {

// Second-derivative stencil of one triangle: d^2x/du^2 at the triangle is approximated by
// sum_j w_uu[j] x[vertex[j]] (exact when x is a quadratic function of (u, v)); the same for
// vv and uv.
struct BendingStencil {
  static constexpr int kMaxNodes = 6;
  int count = 0;                  // nodes used: 3 triangle corners + up to 3 extra vertices
  int vertex[kMaxNodes] = {};     // vertex ids; [0..2] are the triangle's corners
  double w_uu[kMaxNodes] = {};    // 1/m^2
  double w_vv[kMaxNodes] = {};    // 1/m^2
  double w_uv[kMaxNodes] = {};    // 1/m^2
  double area = 0.0;              // rest area of the triangle, m^2
};

struct BendingModel {
  double bending_weft = 0.0;  // D11 = B_weft, N*m: bending that curves the u (weft) yarns
  double bending_warp = 0.0;  // D22 = B_warp, N*m: bending that curves the v (warp) yarns
  double twist = 0.0;         // D66 = (B_weft + B_warp)/4, N*m
  int num_vertices = 0;
  std::vector<BendingStencil> stencils;  // (T) one per triangle

  // Assembled constant stiffness Q (V x V, N/m), symmetric positive semi-definite:
  // E = 1/2 sum_c X_c^T Q X_c over the three coordinates c.
  Eigen::SparseMatrix<double, Eigen::RowMajor> stiffness;

  // Diagnostics of the precomputation.
  int boundary_stencils = 0;  // triangles with a boundary edge (extra vertices chosen nearby)
  int fallback_stencils = 0;  // interior triangles whose hinge apices were ill-conditioned
  double max_amplification = 0.0;  // max over triangles of |w|_F l^2 (l^2: mean squared edge)
};

// Precomputes the bending model of a flat rest sheet with coordinates `rest_uv` (m).
// `bending_weft` is B for curvature along u (N*m); `bending_warp` is B for curvature along
// v, < 0 meaning the same as `bending_weft` (isotropic). Throws InputError for a vertex id
// out of range, a degenerate rest triangle, or a negative `bending_weft`.
BendingModel build_bending(const TriList& triangles, const Vec2List& rest_uv,
                           double bending_weft, double bending_warp);

// Bending energy at positions x (V), J.
double bending_energy(const BendingModel& model, const Vec3List& x);

// Adds the bending forces -dE/dx (N) to f (V).
void add_bending_forces(const BendingModel& model, const Vec3List& x, Vec3List& f);

// Adds df/dx (N/m) = -Q (x) I3, the exact Jacobian of the bending forces. It does not
// depend on x (accepted for a uniform interface), is symmetric and negative semi-definite,
// so no definiteness projection is needed for Newton / conjugate-gradient solves. Only the
// three diagonal entries of each 3x3 vertex block are added (the others are zero).
void add_bending_jacobian(const BendingModel& model, const Vec3List& x, BlockTriplets& dfdx);

}  // namespace tissu
