#include "physics/air_damping.h"

namespace tissu {

void add_air_damping(const Model& model, double c, const Vec3List& v, int first, int end,
                     VertexForces out) {
  for (int i = first; i < end; ++i) out[i] -= (c * model.lumped_area[i]) * v[i];
}

void add_air_damping_jacobian(const Model& model, double c, JacobianSink& sink) {
  if (sink.cv == 0.0) return;
  for (int i = 0; i < model.num_vertices(); ++i) {
    sink.add_identity(i, i, -sink.cv * c * model.lumped_area[i]);
  }
}

}  // namespace tissu
