// The force pipeline: the sum of the force terms the scene declared. A term the scene does
// not declare is skipped here and costs nothing.
#pragma once

#include "core/types.h"
#include "physics/block_triplets.h"
#include "physics/model.h"

namespace tissu {

// f = membrane (+ bending) + gravity + air damping + wind at (x, v, t). N per vertex.
void compute_forces(const Model& model, const Vec3List& x, const Vec3List& v, double t,
                    Vec3List& f);

// Gravity m g (N per vertex).
void add_gravity(const Model& model, const Vec3& g, Vec3List& f);

// Viscous friction (eq. 7) per unit area: -C * lumped_area * v (N).
void add_air_damping(const Model& model, double c, const Vec3List& v, Vec3List& f);

// Wind (eq. 8, interpreted): drag * A * ((w - v_tri) . n) n per triangle, a third per vertex.
void add_wind(const Model& model, const Wind& wind, const Vec3List& x, const Vec3List& v,
              double t, Vec3List& f);

// Jacobians of the total force: df/dx (N/m) and df/dv (N*s/m). The wind's dependence on
// the normal's direction is left out (treated explicitly); see docs/physics.md.
void compute_force_jacobian(const Model& model, const Vec3List& x, const Vec3List& v, double t,
                            bool project_psd, BlockTriplets& dfdx, BlockTriplets& dfdv);

}  // namespace tissu
