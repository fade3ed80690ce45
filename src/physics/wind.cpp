#include "physics/wind.h"

namespace tissu {

void add_wind(const Model& model, const Wind& wind, const Vec3List& x, const Vec3List& v,
              double t, int first, int end, VertexForces out) {
  const Vec3 w = wind.at(t);
  for (int k = first; k < end; ++k) {
    const Tri& tri = model.triangles[k];
    const Vec3 cross = (x[tri[1]] - x[tri[0]]).cross(x[tri[2]] - x[tri[0]]);
    const double twice_area = cross.norm();
    if (twice_area <= 0.0) continue;
    const Vec3 n = cross / twice_area;
    const Vec3 relative = w - (v[tri[0]] + v[tri[1]] + v[tri[2]]) / 3.0;
    // Current area (the wind sees the deformed triangle), a third to each corner.
    const Vec3 corner = (wind.drag * 0.5 * twice_area * relative.dot(n) / 3.0) * n;
    for (int j = 0; j < 3; ++j) out[tri[j]] += corner;
  }
}

namespace {

// Skew matrix [a]x with [a]x b = a x b.
Mat3 skew(const Vec3& a) {
  Mat3 m;
  m << 0, -a.z(), a.y(), a.z(), 0, -a.x(), -a.y(), a.x(), 0;
  return m;
}

}  // namespace

// Velocity part: each corner's force depends on the mean corner velocity, so
// df_i/dv_j = -drag (A/3) (1/3) n n^T for every corner pair.
// Position part: with c = (x1 - x0) x (x2 - x0) (twice the area times n), each corner's
// force is g(c) = drag/6 (r . c) c / |c| (r: relative wind velocity), so
// dg/dc = drag/6 ((r . c)/|c| I + c r^T / |c| - (r . c) c c^T / |c|^3) and
// dc/dx1 = -[e2]x, dc/dx2 = [e1]x, dc/dx0 = [e2 - e1]x (e1 = x1 - x0, e2 = x2 - x0).
void add_wind_jacobian(const Model& model, const Wind& wind, const Vec3List& x,
                       const Vec3List& v, double t, bool position_part, int first, int end,
                       JacobianSink& sink) {
  const bool with_x = position_part && sink.cx != 0.0;
  if (!with_x && sink.cv == 0.0) return;
  const Vec3 w = wind.at(t);
  Mat3 blocks[9];
  for (int k = first; k < end; ++k) {
    const Tri& tri = model.triangles[k];
    const Vec3 e1 = x[tri[1]] - x[tri[0]], e2 = x[tri[2]] - x[tri[0]];
    const Vec3 c = e1.cross(e2);
    const double len = c.norm();
    if (len <= 0.0) continue;
    const Vec3 n = c / len;
    const Mat3 velocity_block = -(sink.cv * wind.drag * 0.5 * len / 9.0) * (n * n.transpose());
    for (Mat3& b : blocks) b = velocity_block;
    if (with_x) {
      const Vec3 r = w - (v[tri[0]] + v[tri[1]] + v[tri[2]]) / 3.0;
      const double rc = r.dot(c);
      const Mat3 dg_dc = (wind.drag / 6.0) * ((rc / len) * Mat3::Identity() +
                                              (c * r.transpose()) / len -
                                              (rc / (len * len * len)) * (c * c.transpose()));
      const Mat3 dc_dx[3] = {skew(e2 - e1), -skew(e2), skew(e1)};
      for (int j = 0; j < 3; ++j) {
        const Mat3 column = sink.cx * (dg_dc * dc_dx[j]);
        for (int i = 0; i < 3; ++i) blocks[3 * i + j] += column;
      }
    }
    sink.add_triangle(k, tri, blocks);
  }
}

}  // namespace tissu
