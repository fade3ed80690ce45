#include "physics/gravity.h"

namespace tissu {

void add_gravity(const Model& model, const Vec3& g, int first, int end, VertexForces out) {
  for (int i = first; i < end; ++i) out[i] += model.mass[i] * g;
}

}  // namespace tissu
