// Gravity: m_i g on every vertex (N), with m_i the lumped mass (Model::mass).
// Its Jacobian is zero.
#pragma once

#include "physics/force_term.h"
#include "physics/model.h"

namespace tissu {

// Adds m_i g (g in m/s^2) for vertices [first, end).
void add_gravity(const Model& model, const Vec3& g, int first, int end, VertexForces out);

}  // namespace tissu
