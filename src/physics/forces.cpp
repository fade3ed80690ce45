#include "physics/forces.h"

#include <algorithm>

#include "physics/bending.h"
#include "physics/membrane.h"

namespace tissu {

void add_gravity(const Model& model, const Vec3& g, Vec3List& f) {
  for (size_t i = 0; i < f.size(); ++i) f[i] += model.mass[i] * g;
}

void add_air_damping(const Model& model, double c, const Vec3List& v, Vec3List& f) {
  for (size_t i = 0; i < f.size(); ++i) f[i] -= (c * model.lumped_area[i]) * v[i];
}

void add_wind(const Model& model, const Wind& wind, const Vec3List& x, const Vec3List& v,
              double t, Vec3List& f) {
  const Vec3 w = wind.at(t);
  for (const Tri& tri : model.triangles) {
    const Vec3 cross = (x[tri[1]] - x[tri[0]]).cross(x[tri[2]] - x[tri[0]]);
    const double twice_area = cross.norm();
    if (twice_area <= 0.0) continue;
    const Vec3 n = cross / twice_area;
    const Vec3 relative = w - (v[tri[0]] + v[tri[1]] + v[tri[2]]) / 3.0;
    // Current area (the wind sees the deformed triangle), a third to each corner.
    const Vec3 corner = (wind.drag * 0.5 * twice_area * relative.dot(n) / 3.0) * n;
    for (int k = 0; k < 3; ++k) f[tri[k]] += corner;
  }
}

void compute_forces(const Model& model, const Vec3List& x, const Vec3List& v, double t,
                    Vec3List& f) {
  std::fill(f.begin(), f.end(), Vec3::Zero());
  add_membrane_forces(model, x, &v, f);
  if (model.bending) add_bending_forces(*model.bending, x, f);
  if (model.gravity) add_gravity(model, *model.gravity, f);
  if (model.air_damping) add_air_damping(model, *model.air_damping, v, f);
  if (model.wind) add_wind(model, *model.wind, x, v, t, f);
}

namespace {

// Skew matrix [a]x with [a]x b = a x b.
Mat3 skew(const Vec3& a) {
  Mat3 m;
  m << 0, -a.z(), a.y(), a.z(), 0, -a.x(), -a.y(), a.x(), 0;
  return m;
}

// Position derivative of the wind. With c = (x1 - x0) x (x2 - x0) (twice the area times
// n), each corner's force is g(c) = drag/6 (r . c) c / |c| (r: relative wind velocity), so
// dg/dc = drag/6 ((r . c)/|c| I + c r^T / |c| - (r . c) c c^T / |c|^3) and
// dc/dx1 = -[e2]x, dc/dx2 = [e1]x, dc/dx0 = [e2 - e1]x (e1 = x1 - x0, e2 = x2 - x0).
// Not symmetric (a follower load).
void add_wind_position_jacobian(const Model& model, const Wind& wind, const Vec3List& x,
                                const Vec3List& v, double t, BlockTriplets& dfdx) {
  const Vec3 w = wind.at(t);
  for (const Tri& tri : model.triangles) {
    const Vec3 e1 = x[tri[1]] - x[tri[0]], e2 = x[tri[2]] - x[tri[0]];
    const Vec3 c = e1.cross(e2);
    const double len = c.norm();
    if (len <= 0.0) continue;
    const Vec3 r = w - (v[tri[0]] + v[tri[1]] + v[tri[2]]) / 3.0;
    const double rc = r.dot(c);
    const Mat3 dg_dc = (wind.drag / 6.0) * ((rc / len) * Mat3::Identity() +
                                            (c * r.transpose()) / len -
                                            (rc / (len * len * len)) * (c * c.transpose()));
    const Mat3 dc_dx[3] = {skew(e2 - e1), -skew(e2), skew(e1)};
    for (int j = 0; j < 3; ++j) {
      const Mat3 block = dg_dc * dc_dx[j];
      for (int i = 0; i < 3; ++i) dfdx.add(tri[i], tri[j], block);
    }
  }
}

}  // namespace

void compute_force_jacobian(const Model& model, const Vec3List& x, const Vec3List& v, double t,
                            bool project_psd, BlockTriplets& dfdx, BlockTriplets& dfdv) {
  add_membrane_jacobian(model, x, project_psd, dfdx, &dfdv, &v);
  if (model.bending) add_bending_jacobian(*model.bending, x, dfdx);
  if (model.air_damping) {
    for (int i = 0; i < model.num_vertices(); ++i) {
      dfdv.add(i, i, -(*model.air_damping * model.lumped_area[i]) * Mat3::Identity());
    }
  }
  if (model.wind) {
    for (const Tri& tri : model.triangles) {
      const Vec3 cross = (x[tri[1]] - x[tri[0]]).cross(x[tri[2]] - x[tri[0]]);
      const double twice_area = cross.norm();
      if (twice_area <= 0.0) continue;
      const Vec3 n = cross / twice_area;
      const Mat3 block = -(model.wind->drag * 0.5 * twice_area / 9.0) * (n * n.transpose());
      for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) dfdv.add(tri[i], tri[j], block);
      }
    }
    // The solver's (projected) Jacobian must keep the system symmetric for CG: there the
    // wind's position dependence stays explicit (quasi-Newton).
    if (!project_psd) add_wind_position_jacobian(model, *model.wind, x, v, t, dfdx);
  }
}

}  // namespace tissu
