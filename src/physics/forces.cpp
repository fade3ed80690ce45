#include "physics/forces.h"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "physics/bending.h"
#include "physics/membrane.h"
#include "physics/parallel.h"

namespace tissu {

void add_gravity(const Model& model, const Vec3& g, Vec3List& f) {
  add_gravity(model, g, 0, static_cast<int>(f.size()), f);
}

void add_gravity(const Model& model, const Vec3& g, int first, int end, Vec3List& f) {
  for (int i = first; i < end; ++i) f[i] += model.mass[i] * g;
}

void add_air_damping(const Model& model, double c, const Vec3List& v, Vec3List& f) {
  add_air_damping(model, c, v, 0, static_cast<int>(f.size()), f);
}

void add_air_damping(const Model& model, double c, const Vec3List& v, int first, int end,
                     Vec3List& f) {
  for (int i = first; i < end; ++i) f[i] -= (c * model.lumped_area[i]) * v[i];
}

void add_wind(const Model& model, const Wind& wind, const Vec3List& x, const Vec3List& v,
              double t, Vec3List& f) {
  if (f.empty()) return;
  add_wind(model, wind, x, v, t, 0, model.num_triangles(), 0, f.data());
}

void add_wind(const Model& model, const Wind& wind, const Vec3List& x, const Vec3List& v,
              double t, int first, int end, int vertex_offset, Vec3* out) {
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
    for (int j = 0; j < 3; ++j) out[tri[j] - vertex_offset] += corner;
  }
}

void ChunkedForces::plan(const Model& model) {
  if (planned_mesh == model.mesh_id && planned_triangles == model.triangles.data() &&
      num_vertices == model.num_vertices() && num_triangles == model.num_triangles() &&
      bending == (model.bending != nullptr)) {
    return;
  }
  if (model.bending && model.bending->num_vertices != model.num_vertices()) {
    throw std::invalid_argument("forces: the bending model has " +
                                std::to_string(model.bending->num_vertices) +
                                " vertices, the mesh " + std::to_string(model.num_vertices()));
  }
  planned_mesh = model.mesh_id;
  planned_triangles = model.triangles.data();
  bending = model.bending != nullptr;
  num_vertices = model.num_vertices();
  num_triangles = model.num_triangles();
  chunks.clear();
  size_t offset = 0;
  const int per_chunk = chunk_triangles(num_triangles);
  for (int first = 0; first < num_triangles; first += per_chunk) {
    Chunk c;
    c.first_triangle = first;
    c.end_triangle = std::min(num_triangles, first + per_chunk);
    c.first_vertex = num_vertices;
    c.end_vertex = 0;
    for (int k = c.first_triangle; k < c.end_triangle; ++k) {
      c.first_vertex = std::min(c.first_vertex, model.triangles[k].minCoeff());
      c.end_vertex = std::max(c.end_vertex, model.triangles[k].maxCoeff() + 1);
    }
    c.offset = offset;
    offset += static_cast<size_t>(c.end_vertex - c.first_vertex);
    chunks.push_back(c);
  }
  partial.assign(offset, Vec3::Zero());

  block_chunk_start.assign(1, 0);
  block_chunks.clear();
  for (int b = 0; b < num_blocks(); ++b) {
    for (int c = 0; c < num_chunks(); ++c) {
      if (chunks[c].first_vertex < block_end(b) && chunks[c].end_vertex > block_begin(b)) {
        block_chunks.push_back(c);
      }
    }
    block_chunk_start.push_back(static_cast<int>(block_chunks.size()));
  }

  std::vector<std::pair<int, int>> by_first_vertex;  // (first vertex, item)
  for (int c = 0; c < num_chunks(); ++c) by_first_vertex.emplace_back(chunks[c].first_vertex, c);
  if (bending) {
    for (int b = 0; b < num_blocks(); ++b) by_first_vertex.emplace_back(block_begin(b), -1 - b);
  }
  std::stable_sort(by_first_vertex.begin(), by_first_vertex.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  // Costs from a profile of the demo: one triangle's membrane forces take about as long as
  // 20 entries of the bending matrix's rows.
  constexpr double kTriangleCost = 20.0;
  const int* row_starts = bending ? model.bending->stiffness.outerIndexPtr() : nullptr;
  stage1_items.clear();
  stage1_cost.clear();
  for (const auto& entry : by_first_vertex) {
    const int item = entry.second;
    stage1_items.push_back(item);
    if (item >= 0) {
      const Chunk& c = chunks[item];
      stage1_cost.push_back(kTriangleCost * (c.end_triangle - c.first_triangle));
    } else {
      const int b = -1 - item;
      stage1_cost.push_back(row_starts[block_end(b)] - row_starts[block_begin(b)]);
    }
  }
}

namespace {

void forces_stage1_chunk(const Model& model, const Vec3List& x, const Vec3List& v, double t,
                         int chunk, ChunkedForces& forces) {
  const ChunkedForces::Chunk& c = forces.chunks[chunk];
  Vec3* out = forces.partial.data() + c.offset;
  std::fill(out, out + (c.end_vertex - c.first_vertex), Vec3::Zero());
  add_membrane_forces(model, x, &v, c.first_triangle, c.end_triangle, c.first_vertex,
                      out[0].data());
  if (model.wind) {
    add_wind(model, *model.wind, x, v, t, c.first_triangle, c.end_triangle, c.first_vertex, out);
  }
}

void forces_stage1_bending(const Model& model, const Vec3List& x, int block,
                           const ChunkedForces& forces, Vec3List& f) {
  const int first = forces.block_begin(block), end = forces.block_end(block);
  std::fill(f.begin() + first, f.begin() + end, Vec3::Zero());
  add_bending_forces(*model.bending, x, forces.origin, first, end, f);
}

}  // namespace

void forces_stage1(const Model& model, const Vec3List& x, const Vec3List& v, double t,
                   int threads, ChunkedForces& forces, Vec3List& f) {
  if (model.bending) forces.origin = bending_origin(x);
  parallel_for(threads, static_cast<int>(forces.stage1_items.size()), [&](int k) {
    const int item = forces.stage1_items[k];
    if (item >= 0) {
      forces_stage1_chunk(model, x, v, t, item, forces);
    } else {
      forces_stage1_bending(model, x, -1 - item, forces, f);
    }
  }, forces.stage1_cost.data());
}

void forces_stage2(const Model& model, const Vec3List& v, int block,
                   const ChunkedForces& forces, Vec3List& f) {
  const int first = forces.block_begin(block), end = forces.block_end(block);
  if (!model.bending) std::fill(f.begin() + first, f.begin() + end, Vec3::Zero());
  for (int k = forces.block_chunk_start[block]; k < forces.block_chunk_start[block + 1]; ++k) {
    const ChunkedForces::Chunk& c = forces.chunks[forces.block_chunks[k]];
    const int lo = std::max(first, c.first_vertex), hi = std::min(end, c.end_vertex);
    for (int i = lo; i < hi; ++i) f[i] += forces.partial[c.offset + (i - c.first_vertex)];
  }
  if (model.gravity) add_gravity(model, *model.gravity, first, end, f);
  if (model.air_damping) add_air_damping(model, *model.air_damping, v, first, end, f);
}

void compute_forces(const Model& model, const Vec3List& x, const Vec3List& v, double t,
                    Vec3List& f, ChunkedForces& scratch, int threads) {
  f.resize(x.size());
  scratch.plan(model);
  forces_stage1(model, x, v, t, threads, scratch, f);
  parallel_for(threads, scratch.num_blocks(),
               [&](int block) { forces_stage2(model, v, block, scratch, f); });
}

void compute_forces(const Model& model, const Vec3List& x, const Vec3List& v, double t,
                    Vec3List& f) {
  ChunkedForces scratch;
  compute_forces(model, x, v, t, f, scratch, 1);
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
