#include "physics/forces.h"

#include "physics/air_damping.h"
#include "physics/bending.h"
#include "physics/force_plan.h"
#include "physics/membrane.h"
#include "physics/step_scratch.h"
#include "physics/wind.h"

namespace tissu {

void compute_forces(const Model& model, const Vec3List& x, const Vec3List& v, double t,
                    Vec3List& f, Workspace& ws) {
  compute_forces(model, x, v, t, f, scratch_of(ws).forces, force_threads(ws.threads, model));
}

void compute_forces(const Model& model, const Vec3List& x, const Vec3List& v, double t,
                    Vec3List& f) {
  ForcePlan plan;
  compute_forces(model, x, v, t, f, plan, 1);
}

void add_force_jacobian(const Model& model, const Vec3List& x, const Vec3List& v, double t,
                        bool project_psd, JacobianSink& sink) {
  const int triangles = model.num_triangles();
  add_membrane_jacobian(model, x, &v, project_psd, 0, triangles, sink);
  if (model.bending) add_bending_jacobian(*model.bending, sink);
  if (model.air_damping) add_air_damping_jacobian(model, *model.air_damping, sink);
  if (model.wind) {
    add_wind_jacobian(model, *model.wind, x, v, t, /*position_part=*/!project_psd, 0, triangles,
                      sink);
  }
}

void compute_force_jacobian(const Model& model, const Vec3List& x, const Vec3List& v, double t,
                            bool project_psd, BlockTriplets& dfdx, BlockTriplets& dfdv) {
  TripletSink position(1.0, 0.0, dfdx), velocity(0.0, 1.0, dfdv);
  add_force_jacobian(model, x, v, t, project_psd, position);
  add_force_jacobian(model, x, v, t, project_psd, velocity);
}

}  // namespace tissu
