// Bending of the cloth sheet (flexural rigidity B, N*m; energy per area B/2 k^2).
//
// Discrete plate energy, summed over the triangles T of the flat rest sheet:
//   E = sum_T A_T/2 (B_weft |x_uu|^2 + B_warp |x_vv|^2 + (B_weft + B_warp) |x_uv|^2),
// where x_uu, x_vv, x_uv are the second derivatives of the 3D position with respect to the
// rest coordinates (u = weft, v = warp), estimated on each triangle as the flux of edge
// gradients through its boundary, 1/A_T sum_e l_e G_e n_e^T. G_e is the mean gradient, at
// the edge's midpoint, of the quadratic patches of the edge's triangles; a triangle's patch
// passes through its 3 corners and the 3 apices of its hinges (nearby vertices replace
// apices missing at boundaries or nearly on a conic with the corners, and needle or cap
// triangles use a least-squares quadratic over their nearby vertices, and their own patch's
// Hessian). The estimate is exact whenever x is a quadratic function of (u, v), on any
// triangulation, and no pattern of vertex values passes for a curvature. Triangles whose
// corners are all pinned are a clamp: no bending, and their edges keep the clamp's slope.
//
// For an isometric deformation of the flat rest sheet (cloth barely stretches) the second
// derivatives are normal to the surface and their norms are the curvatures, so E is the
// orthotropic plate energy 1/2 (D11 k_uu^2 + D22 k_vv^2 + 4 D66 k_uv^2) with D11 = B_weft,
// D22 = B_warp, D66 = (B_weft + B_warp)/4: a sheet rolled on a cylinder of curvature k has
// energy B(phi)/2 k^2 per area, B(phi) = B_weft cos^2 phi + B_warp sin^2 phi, phi being the
// angle between u and the direction along which the sheet curves. Bending about an axis
// along v curves the weft (u) yarns and costs B_weft; about an axis along u, B_warp.
// This is the "isometric bending" idea of Bergou et al. 2006 (quadratic energy, constant
// Hessian, flat sheet in the kernel) with a second-derivative operator that is consistent
// on irregular meshes, where hinge (dihedral-angle or cotangent) energies are not: see
// docs/bending.md.
//
// E is a quadratic form, E = 1/2 sum_{c=x,y,z} X_c^T Q X_c with one constant symmetric
// positive semi-definite V x V matrix Q (N/m) whose kernel is exactly the affine maps of
// the rest plane. Forces are -Q x; the force Jacobian is -Q (x) I3: exact, constant,
// symmetric, negative semi-definite.
#pragma once

#include <Eigen/Sparse>
#include <vector>

#include "core/types.h"
#include "physics/bending_stencil.h"
#include "physics/force_term.h"

namespace tissu {

// The stencils and their diagnostics (BendingStencils, bending_stencil.h), the material
// and the assembled stiffness.
struct BendingModel : BendingStencils {
  double bending_weft = 0.0;  // D11 = B_weft, N*m: bending that curves the u (weft) yarns
  double bending_warp = 0.0;  // D22 = B_warp, N*m: bending that curves the v (warp) yarns
  double twist = 0.0;         // D66 = (B_weft + B_warp)/4, N*m
  int num_vertices = 0;

  // Assembled constant stiffness Q (V x V, N/m), symmetric positive semi-definite:
  // E = 1/2 sum_c X_c^T Q X_c over the three coordinates c.
  Eigen::SparseMatrix<double, Eigen::RowMajor> stiffness;
};

// Precomputes the bending model of a flat rest sheet with coordinates `rest_uv` (m).
// `bending_weft` (N*m) is B for bending that curves the weft (u) yarns, about an axis along
// v; `bending_warp` (N*m) the same for the warp (v) yarns, < 0 meaning the same as
// `bending_weft` (isotropic). Throws InputError for a vertex id
// out of range, a degenerate rest triangle, or a negative `bending_weft`.
BendingModel build_bending(const TriList& triangles, const Vec2List& rest_uv, double bending_weft,
                           double bending_warp, const std::vector<uint8_t>& pinned = {});

// Bending energy at positions x (V), J.
double bending_energy(const BendingModel& model, const Vec3List& x);

// The mean of x (m): forces are computed from x - origin, so round-off stays proportional
// to the sheet's size, not to its distance from the world origin.
Vec3 bending_origin(const Vec3List& x);

// A position minus the origin (m), padded to four doubles (the fourth 0) and aligned so
// that the vectorised kernel reads each with one load.
struct alignas(32) CenteredPoint {
  double c[4];
};
static_assert(sizeof(CenteredPoint) == 4 * sizeof(double), "the kernel reads 4 doubles a vertex");
using CenteredPositions = std::vector<CenteredPoint>;

// xc = x - origin for every vertex (xc resized to x's size).
void center_positions(const Vec3List& x, const Vec3& origin, CenteredPositions& xc);
// xc = x - bending_origin(x), what add_bending_forces reads. Throws std::invalid_argument
// when x does not have the model's vertex count.
void center_positions(const BendingModel& model, const Vec3List& x, CenteredPositions& xc);

// Adds the bending forces -dE/dx (N) of vertices [first, end) to out:
// f_i -= sum_j Q_ij xc_j, with xc = center_positions(model, x) for the whole mesh (the
// vertex count is checked there, not here, on the step's threads).
// Each vertex reads its own row of Q, so vertex blocks can run on separate threads.
// Vectorised (bending_simd.h); the same bits as the scalar loop below.
void add_bending_forces(const BendingModel& model, const CenteredPositions& xc, int first,
                        int end, VertexForces out);
// The same from x and the origin (centres the whole mesh first). Throws
// std::invalid_argument when x does not have the model's vertex count.
void add_bending_forces(const BendingModel& model, const Vec3List& x, const Vec3& origin,
                        int first, int end, VertexForces out);
// The same, one coordinate after the other: the reference.
void add_bending_forces_scalar(const BendingModel& model, const Vec3List& x,
                               const Vec3& origin, int first, int end, VertexForces out);

// Adds c_x df/dx = -c_x Q (x) I3 (N/m), the exact Jacobian of the bending forces: constant,
// symmetric and negative semi-definite, so no definiteness projection is needed for
// Newton / conjugate-gradient solves. Each vertex pair's block couples each coordinate
// only with itself (JacobianSink::add_identity). No velocity dependence.
void add_bending_jacobian(const BendingModel& model, JacobianSink& sink);

}  // namespace tissu
