// Implicit integrators: backward Euler (the paper's eq. 11) and BDF-2, solved with Newton's
// method on the velocity update, the analytic force Jacobian and preconditioned conjugate
// gradients. Pinned vertices are constraints filtered out of the solve.
#pragma once

#include "physics/model.h"
#include "physics/step.h"

namespace tissu {

// Advances positions and velocities by one implicit step of model.integrator.
void integrate_implicit(const Model& model, State& state, Workspace& ws);

}  // namespace tissu
