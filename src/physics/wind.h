// Wind (the paper's eq. 8, interpreted; docs/physics.md): each triangle feels
//   F = drag * A * ((w(t) - v_tri) . n) n,
// spread equally over its three corners, with A its current area (m^2), n its unit normal,
// w(t) the wind velocity (Wind::at, m/s) and v_tri the mean of its corner velocities.
// Degenerate (zero-area) triangles feel nothing.
#pragma once

#include "physics/force_term.h"
#include "physics/model.h"

namespace tissu {

// Adds the wind forces of triangles [first, end).
void add_wind(const Model& model, const Wind& wind, const Vec3List& x, const Vec3List& v,
              double t, int first, int end, VertexForces out);

// Adds the Jacobian of triangles [first, end): df/dv = -drag A / 9 n n^T per corner pair,
// and with `position_part` the position derivative (the wind is a follower load: that
// part is not symmetric, so the implicit solver leaves it out and treats it explicitly).
void add_wind_jacobian(const Model& model, const Wind& wind, const Vec3List& x,
                       const Vec3List& v, double t, bool position_part, int first, int end,
                       JacobianSink& sink);

}  // namespace tissu
