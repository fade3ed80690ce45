// Viscous friction with the air (the paper's eq. 7), per unit cloth area so that results
// do not depend on the mesh resolution: f_i = -c a_i v_i (N), with c in N*s/m^3 and a_i
// the vertex's lumped area (m^2). Its Jacobian: df_i/dv_i = -c a_i I (N*s/m).
#pragma once

#include "physics/force_term.h"
#include "physics/model.h"

namespace tissu {

// Adds -c a_i v_i for vertices [first, end).
void add_air_damping(const Model& model, double c, const Vec3List& v, int first, int end,
                     VertexForces out);

// Adds c_v df/dv = -c_v c a_i I for every vertex (no position dependence).
void add_air_damping_jacobian(const Model& model, double c, JacobianSink& sink);

}  // namespace tissu
