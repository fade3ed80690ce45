#include "physics/vertex_pass.h"

namespace tissu {

void integrate_vertices(const Model &model, int first, int end,
                        const Vec3List &f, Vec3List &x, Vec3List &v) {
  const double h = model.dt;
  const double *inv_mass = model.inv_mass.data();
  switch (model.integrator) {
  case Integrator::ExplicitEuler:
    for (int i = first; i < end; ++i) {
      x[i] += h * v[i];
      v[i] += (h * inv_mass[i]) * f[i];
    }
    break;
  case Integrator::SymplecticEuler:
    for (int i = first; i < end; ++i) {
      v[i] += (h * inv_mass[i]) * f[i];
      x[i] += h * v[i];
    }
    break;
  case Integrator::BenameurDjedi:
    for (int i = first; i < end; ++i) {
      v[i] += (h * inv_mass[i] / 2.0) * f[i];
      x[i] += h * v[i];
    }
    break;
  default:
    break;
  }
}

void check_vertex(int i, const Vec3 &x, const Vec3 &v, BlockCheck &check) {
  if (check.first_bad >= 0)
    return;
  const bool finite = x.allFinite();
  if (!finite || !v.allFinite()) {
    check.first_bad = i;
    check.bad_position = !finite;
    return;
  }
  const double s2 = v.squaredNorm();
  if (s2 > check.top_speed2) {
    check.top_speed2 = s2;
    check.fastest = i;
  }
}

void finish_block_scalar(const Model &model, const ForcePlan &plan, int block,
                         Vec3List &f, Vec3List &x, Vec3List &v,
                         BlockCheck *check) {
  const int first = plan.block_begin(block), end = plan.block_end(block);
  forces_stage2(model, v, block, plan, f);
  integrate_vertices(model, first, end, f, x, v);
  if (check == nullptr)
    return;
  for (int i = first; i < end; ++i)
    check_vertex(i, x[i], v[i], *check);
}

} // namespace tissu
