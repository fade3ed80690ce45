#include "physics/membrane.h"

#include <algorithm>
#include <cmath>

#include "physics/biphasic.h"
#include "physics/membrane_simd.h"

namespace tissu {

namespace {

struct Gradients {
  Vec3 U, V;  // dP/du, dP/dv (eq. 3)
};

inline Gradients deformation(const TriangleRest& r, const Vec3& a, const Vec3& b, const Vec3& c) {
  return {r.ru[0] * a + r.ru[1] * b + r.ru[2] * c, r.rv[0] * a + r.rv[1] * b + r.rv[2] * c};
}

inline Vec3 green_strain(const Gradients& g) {
  return Vec3(0.5 * (g.U.squaredNorm() - 1.0), 0.5 * (g.V.squaredNorm() - 1.0), g.U.dot(g.V));
}

// de/dt of the Green strain from the gradients g and their rates gd = (dU/dt, dV/dt), 1/s.
inline Vec3 strain_rate(const Gradients& g, const Gradients& gd) {
  return Vec3(g.U.dot(gd.U), g.V.dot(gd.V), g.U.dot(gd.V) + gd.U.dot(g.V));
}

// Eq. 6 regrouped: F_j = -A ((s_uu r_uj + s_uv r_vj) U + (s_vv r_vj + s_uv r_uj) V).
inline Vec3 corner_force(const TriangleRest& r, const Gradients& g, const Vec3& s, int j) {
  return -r.area * ((s[0] * r.ru[j] + s[2] * r.rv[j]) * g.U + (s[1] * r.rv[j] + s[2] * r.ru[j]) * g.V);
}

// The hot loop of every explicit step: gather, strain, stress, scatter, written on plain
// doubles so the compiler keeps everything in registers. Triangles [first, end) add their
// corner forces to out[3 * (vertex - vertex_offset) + k].
template <bool kDamped>
void accumulate_forces(const Model& model, const Vec3List& x, const Vec3List* v, int first,
                       int end, int vertex_offset, double* out) {
  const Mat3 E = model.material.stiffness();
  const double e00 = E(0, 0), e01 = E(0, 1), e02 = E(0, 2), e11 = E(1, 1), e12 = E(1, 2),
               e22 = E(2, 2);
  const double tau = model.material.damping;
  const double* px = x[0].data();
  const double* pv = kDamped ? (*v)[0].data() : nullptr;
  const int out_offset = 3 * vertex_offset;
  const Tri* tris = model.triangles.data();
  const TriangleRest* rests = model.rest.data();
  for (int t = first; t < end; ++t) {
    const int ia = 3 * tris[t][0], ib = 3 * tris[t][1], ic = 3 * tris[t][2];
    const TriangleRest& r = rests[t];
    double U[3], V[3];
    for (int k = 0; k < 3; ++k) {
      U[k] = r.ru[0] * px[ia + k] + r.ru[1] * px[ib + k] + r.ru[2] * px[ic + k];
      V[k] = r.rv[0] * px[ia + k] + r.rv[1] * px[ib + k] + r.rv[2] * px[ic + k];
    }
    double euu = 0.5 * (U[0] * U[0] + U[1] * U[1] + U[2] * U[2] - 1.0);
    double evv = 0.5 * (V[0] * V[0] + V[1] * V[1] + V[2] * V[2] - 1.0);
    double euv = U[0] * V[0] + U[1] * V[1] + U[2] * V[2];
    if constexpr (kDamped) {
      // Strain rate from the velocity gradients dU/dt, dV/dt.
      double Ud[3], Vd[3];
      for (int k = 0; k < 3; ++k) {
        Ud[k] = r.ru[0] * pv[ia + k] + r.ru[1] * pv[ib + k] + r.ru[2] * pv[ic + k];
        Vd[k] = r.rv[0] * pv[ia + k] + r.rv[1] * pv[ib + k] + r.rv[2] * pv[ic + k];
      }
      euu += tau * (U[0] * Ud[0] + U[1] * Ud[1] + U[2] * Ud[2]);
      evv += tau * (V[0] * Vd[0] + V[1] * Vd[1] + V[2] * Vd[2]);
      euv += tau * (U[0] * Vd[0] + U[1] * Vd[1] + U[2] * Vd[2] + Ud[0] * V[0] + Ud[1] * V[1] +
                    Ud[2] * V[2]);
    }
    const double suu = -r.area * (e00 * euu + e01 * evv + e02 * euv);
    const double svv = -r.area * (e01 * euu + e11 * evv + e12 * euv);
    const double suv = -r.area * (e02 * euu + e12 * evv + e22 * euv);
    const int corner[3] = {ia - out_offset, ib - out_offset, ic - out_offset};
    for (int j = 0; j < 3; ++j) {
      const double alpha = suu * r.ru[j] + suv * r.rv[j];
      const double beta = svv * r.rv[j] + suv * r.ru[j];
      double* o = out + corner[j];
      o[0] += alpha * U[0] + beta * V[0];
      o[1] += alpha * U[1] + beta * V[1];
      o[2] += alpha * U[2] + beta * V[2];
    }
  }
}

// The stress (N/m) of the biphasic membrane (biphasic.h) at the mapped strain b with strain
// rate `rate` (1/s): D E e~ + tau D E D de/dt.
inline Vec3 biphasic_stress(const Mat3& E, const BiphasicStrain& b, double tau,
                            const Vec3& rate) {
  return b.slope.cwiseProduct(E * (b.mapped + tau * b.slope.cwiseProduct(rate)));
}

// Triangles [first, end) of a material whose compression ratio is below 1: the forces of
// eq. 6 with the biphasic stress, viscous too when `v` is given.
void accumulate_biphasic_forces(const Model& model, const Vec3List& x, const Vec3List* v,
                                int first, int end, VertexForces out) {
  const Mat3 E = model.material.stiffness();
  const double kappa = model.material.compression_ratio;
  const double tau = v != nullptr ? model.material.damping : 0.0;
  for (int t = first; t < end; ++t) {
    const Tri& tri = model.triangles[t];
    const TriangleRest& r = model.rest[t];
    const Gradients g = deformation(r, x[tri[0]], x[tri[1]], x[tri[2]]);
    Vec3 rate = Vec3::Zero();
    if (tau > 0.0) rate = strain_rate(g, deformation(r, (*v)[tri[0]], (*v)[tri[1]], (*v)[tri[2]]));
    const Vec3 stress = biphasic_stress(E, biphasic_strain(green_strain(g), kappa), tau, rate);
    for (int j = 0; j < 3; ++j) out[tri[j]] += corner_force(r, g, stress, j);
  }
}

}  // namespace

Vec3 triangle_strain(const TriangleRest& rest, const Vec3& a, const Vec3& b, const Vec3& c) {
  return green_strain(deformation(rest, a, b, c));
}

double triangle_energy(const TriangleRest& rest, const Mat3& E, const Vec3& a, const Vec3& b,
                       const Vec3& c, double compression_ratio) {
  const Vec3 e = biphasic_strain(triangle_strain(rest, a, b, c), compression_ratio).mapped;
  return 0.5 * rest.area * e.dot(E * e);
}

void triangle_forces(const TriangleRest& rest, const Mat3& E, const Vec3 x[3], Vec3 f[3],
                     double compression_ratio) {
  const Gradients g = deformation(rest, x[0], x[1], x[2]);
  const Vec3 s = biphasic_stress(E, biphasic_strain(green_strain(g), compression_ratio), 0.0,
                                 Vec3::Zero());
  for (int j = 0; j < 3; ++j) f[j] = corner_force(rest, g, s, j);
}

void add_membrane_forces(const Model& model, const Vec3List& x, const Vec3List* v, int first,
                         int end, VertexForces out) {
  const MembraneLayout* layout = model.membrane_layout.get();
  if (layout && layout->mesh_id == model.mesh_id &&
      layout->num_triangles == model.num_triangles() && model.material.compression_ratio >= 1.0) {
    add_membrane_forces_simd(model, *layout, x, v, first, end, out);
  } else {
    add_membrane_forces_scalar(model, x, v, first, end, out);
  }
}

void add_membrane_forces_scalar(const Model& model, const Vec3List& x, const Vec3List* v,
                                int first, int end, VertexForces out) {
  double* base = out.data[0].data();
  if (model.material.compression_ratio < 1.0) {
    accumulate_biphasic_forces(model, x, v, first, end, out);
  } else if (model.material.damping > 0.0 && v != nullptr) {
    accumulate_forces<true>(model, x, v, first, end, out.first_vertex, base);
  } else {
    accumulate_forces<false>(model, x, nullptr, first, end, out.first_vertex, base);
  }
}

double membrane_energy(const Model& model, const Vec3List& x) {
  const Mat3 E = model.material.stiffness();
  const double kappa = model.material.compression_ratio;
  double total = 0.0;
  for (size_t t = 0; t < model.triangles.size(); ++t) {
    const Tri& tri = model.triangles[t];
    total += triangle_energy(model.rest[t], E, x[tri[0]], x[tri[1]], x[tri[2]], kappa);
  }
  return total;
}

void triangle_energies(const Model& model, const Vec3List& x, std::vector<double>& energies) {
  const Mat3 E = model.material.stiffness();
  const double kappa = model.material.compression_ratio;
  energies.resize(model.triangles.size());
  for (size_t t = 0; t < model.triangles.size(); ++t) {
    const Tri& tri = model.triangles[t];
    energies[t] = triangle_energy(model.rest[t], E, x[tri[0]], x[tri[1]], x[tri[2]], kappa);
  }
}

double membrane_energy_change(const Model& model, const Vec3List& x,
                              const std::vector<double>& before) {
  const Mat3 E = model.material.stiffness();
  const double kappa = model.material.compression_ratio;
  double change = 0.0;
  for (size_t t = 0; t < model.triangles.size(); ++t) {
    const Tri& tri = model.triangles[t];
    change += triangle_energy(model.rest[t], E, x[tri[0]], x[tri[1]], x[tri[2]], kappa) - before[t];
  }
  return change;
}

double max_principal_strain(const Model& model, const Vec3List& x) {
  double worst = 0.0;
  for (size_t t = 0; t < model.triangles.size(); ++t) {
    const Tri& tri = model.triangles[t];
    const Vec3 e = triangle_strain(model.rest[t], x[tri[0]], x[tri[1]], x[tri[2]]);
    // Principal values of [[e_uu, e_uv/2], [e_uv/2, e_vv]] (e_uv is engineering shear).
    const double mean = 0.5 * (e[0] + e[1]);
    const double radius = std::hypot(0.5 * (e[0] - e[1]), 0.5 * e[2]);
    worst = std::max(worst, mean + radius);
  }
  return worst;
}

namespace {

// The 2x2 stress [[s_uu, s_uv], [s_uv, s_vv]], N/m.
Eigen::Matrix2d stress_matrix(const Vec3& s) {
  Eigen::Matrix2d S;
  S << s[0], s[2], s[2], s[1];
  return S;
}

// The nearest positive semi-definite 2x2 stress: eigenvalues below zero set to zero. With
// eigenvalues l1 > 0 > l2 it is l1 times the projector (S - l2 I) / (l1 - l2).
Eigen::Matrix2d nearest_psd(const Vec3& s) {
  const double mean = 0.5 * (s[0] + s[1]);
  const double radius = std::hypot(0.5 * (s[0] - s[1]), s[2]);
  const double high = mean + radius, low = mean - radius;
  if (low >= 0.0) return stress_matrix(s);
  if (high <= 0.0) return Eigen::Matrix2d::Zero();
  Eigen::Matrix2d S = stress_matrix(s);
  S.diagonal().array() -= low;
  return (high / (high - low)) * S;
}

// r_i^T S r_j with r_i = (r_ui, r_vi): the geometric (stress) term of block (i, j) is
// -c_x A times it on the diagonal.
double geometric_term(const TriangleRest& r, const Eigen::Matrix2d& S, int i, int j) {
  return r.ru[i] * r.ru[j] * S(0, 0) + r.rv[i] * r.rv[j] * S(1, 1) +
         (r.ru[i] * r.rv[j] + r.rv[i] * r.ru[j]) * S(0, 1);
}

// Weight of the material term J_i E J_j^T in a block: -A (c_x + c_v tau).
double material_weight_of(const TriangleRest& r, double cx, double cv, double tau) {
  return -r.area * (cx + cv * tau);
}

// The nine blocks of a triangle whose Jacobian is symmetric (linear material, and no
// unsymmetric viscous term). de_a/dx_i = [U V] C_i e_a with C_i = [[r_ui, 0, r_vi],
// [0, r_vi, r_ui]], so J_i E J_j^T = [U V] K_ij [U V]^T with the 2x2 K_ij = C_i E C_j^T:
// each block is four outer products of U and V, and block (j, i) is block (i, j)
// transposed. The geometric term adds -c_x A (r_i^T S r_j) I, r_i = (r_ui, r_vi).
void add_symmetric_blocks(const TriangleRest& r, const Gradients& g, const Mat3& E,
                          const Eigen::Matrix2d& S, double material_weight, double cx,
                          Mat3 blocks[9]) {
  Eigen::Matrix<double, 2, 3> CE[3];  // C_i E
  for (int i = 0; i < 3; ++i) {
    Eigen::Matrix<double, 2, 3> C;
    C << r.ru[i], 0.0, r.rv[i], 0.0, r.rv[i], r.ru[i];
    CE[i] = material_weight * (C * E);
  }
  const Mat3 UU = g.U * g.U.transpose(), UV = g.U * g.V.transpose(),
             VV = g.V * g.V.transpose();
  for (int i = 0; i < 3; ++i) {
    for (int j = i; j < 3; ++j) {
      // K = (C_i E) C_j^T, weighted.
      const double k00 = CE[i](0, 0) * r.ru[j] + CE[i](0, 2) * r.rv[j];
      const double k01 = CE[i](0, 1) * r.rv[j] + CE[i](0, 2) * r.ru[j];
      const double k10 = CE[i](1, 0) * r.ru[j] + CE[i](1, 2) * r.rv[j];
      const double k11 = CE[i](1, 1) * r.rv[j] + CE[i](1, 2) * r.ru[j];
      Mat3& block = blocks[3 * i + j];
      block = k00 * UU + k01 * UV + k10 * UV.transpose() + k11 * VV;
      block.diagonal().array() -= cx * r.area * geometric_term(r, S, i, j);
      if (j != i) blocks[3 * j + i] = block.transpose();
    }
  }
}

}  // namespace

// Hessian of W = A/2 e^T E e: H_ij = A [ sum_ab E_ab de_a/dx_i de_b/dx_j^T
//                                        + (R S R^T)_ij I ],  R = [r_u r_v], S = 2x2 stress.
// The force Jacobian is -H. Damping: df/dv = -tau A sum_ab E_ab de_a/dx_i de_b/dx_j^T.
// With a compression ratio below 1 (biphasic.h), the material term has the tangent
// D E D + diag(phi'' (E e~)) (its negative part dropped with `project_psd`), the stress is
// the biphasic one and the damping's material term D E D; the viscous stress's dependence
// on x through D is left out (it is tau de/dt times phi'', negligible at rest).
void add_membrane_jacobian(const Model& model, const Vec3List& x, const Vec3List* v,
                           bool project_psd, int first, int end, JacobianSink& sink) {
  const Mat3 E = model.material.stiffness();
  const double kappa = model.material.compression_ratio;
  const bool biphasic = kappa < 1.0;
  const double tau = model.material.damping;
  const bool viscous = tau > 0.0 && v != nullptr;
  const double cx = sink.cx, cv = tau > 0.0 ? sink.cv : 0.0;
  if (cx == 0.0 && cv == 0.0) return;
  Mat3 blocks[9];
  for (int t = first; t < end; ++t) {
    const Tri& tri = model.triangles[t];
    const TriangleRest& r = model.rest[t];
    const Gradients g = deformation(r, x[tri[0]], x[tri[1]], x[tri[2]]);
    Vec3 strain = green_strain(g);
    Gradients gd{Vec3::Zero(), Vec3::Zero()};  // dU/dt, dV/dt, 1/s
    if (viscous) gd = deformation(r, (*v)[tri[0]], (*v)[tri[1]], (*v)[tri[2]]);
    Vec3 s;            // elastic + viscous stress, N/m
    Mat3 Ev = E;       // material term of the damping, N/m
    Mat3 Ex = E;       // material tangent of the elastic stress, N/m
    if (biphasic) {
      const BiphasicStrain b = biphasic_strain(strain, kappa);
      s = biphasic_stress(E, b, viscous ? tau : 0.0, viscous ? strain_rate(g, gd) : Vec3::Zero());
      Ev = b.slope.asDiagonal() * E * b.slope.asDiagonal();
      Vec3 extra = b.curvature.cwiseProduct(E * b.mapped);
      if (project_psd) extra = extra.cwiseMax(0.0);
      Ex = Ev;
      Ex.diagonal() += extra;
    } else {
      if (viscous) strain += tau * strain_rate(g, gd);
      s = E * strain;
    }

    const Eigen::Matrix2d S = project_psd ? nearest_psd(s) : stress_matrix(s);
    if (!biphasic && !(viscous && !project_psd)) {
      add_symmetric_blocks(r, g, E, S, material_weight_of(r, cx, cv, tau), cx, blocks);
      sink.add_triangle(t, tri, blocks);
      continue;
    }

    // de_a/dx_j as columns: J[j].col(a) for a in (uu, vv, uv).
    Eigen::Matrix3d J[3];
    for (int j = 0; j < 3; ++j) {
      J[j].col(0) = r.ru[j] * g.U;
      J[j].col(1) = r.rv[j] * g.V;
      J[j].col(2) = r.ru[j] * g.V + r.rv[j] * g.U;
    }
    // Force Jacobian blocks: df/dx = -A (material + geometric I [+ viscous]),
    // df/dv = -A tau material.
    const double material_weight = material_weight_of(r, cx, cv, tau);
    for (int i = 0; i < 3; ++i) {
      const Eigen::Matrix3d JiE = J[i] * Ev;
      for (int j = 0; j < 3; ++j) {
        Mat3& block = blocks[3 * i + j];
        if (biphasic) {
          block = -r.area * (cx * (J[i] * Ex * J[j].transpose()) +
                             cv * tau * (JiE * J[j].transpose()));
        } else {
          block = material_weight * (JiE * J[j].transpose());
        }
        block.diagonal().array() -= cx * r.area * geometric_term(r, S, i, j);
        if (viscous && !project_psd && cx != 0.0) {
          // d(strain rate)/dx_j has the columns of J[j] with (U, V) -> (dU/dt, dV/dt).
          Eigen::Matrix3d Jd;
          Jd.col(0) = r.ru[j] * gd.U;
          Jd.col(1) = r.rv[j] * gd.V;
          Jd.col(2) = r.ru[j] * gd.V + r.rv[j] * gd.U;
          block -= (cx * r.area * tau) * (JiE * Jd.transpose());
        }
      }
    }
    sink.add_triangle(t, tri, blocks);
  }
}

}  // namespace tissu
