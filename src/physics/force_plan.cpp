#include "physics/force_plan.h"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "physics/air_damping.h"
#include "physics/bending.h"
#include "physics/gravity.h"
#include "physics/membrane.h"
#include "physics/parallel.h"
#include "physics/wind.h"

namespace tissu {

void ForcePlan::plan(const Model& model) {
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
                         int chunk, ForcePlan& plan, ForceTerms terms) {
  const ForcePlan::Chunk& c = plan.chunks[chunk];
  Vec3* buffer = plan.partial.data() + c.offset;
  std::fill(buffer, buffer + (c.end_vertex - c.first_vertex), Vec3::Zero());
  const VertexForces out{buffer, c.first_vertex};
  const bool all = terms == ForceTerms::All;
  add_membrane_forces(model, x, all ? &v : nullptr, c.first_triangle, c.end_triangle, out);
  if (model.wind && all) {
    add_wind(model, *model.wind, x, v, t, c.first_triangle, c.end_triangle, out);
  }
}

void forces_stage1_bending(const Model& model, int block, const ForcePlan& plan, Vec3List& f) {
  const int first = plan.block_begin(block), end = plan.block_end(block);
  std::fill(f.begin() + first, f.begin() + end, Vec3::Zero());
  add_bending_forces(*model.bending, plan.centered, first, end, VertexForces::of(f));
}

}  // namespace

void forces_stage1(const Model& model, const Vec3List& x, const Vec3List& v, double t,
                   int threads, ForcePlan& plan, Vec3List& f, ForceTerms terms) {
  if (model.bending) center_positions(*model.bending, x, plan.centered);
  parallel_for(threads, static_cast<int>(plan.stage1_items.size()), [&](int k) {
    const int item = plan.stage1_items[k];
    if (item >= 0) {
      forces_stage1_chunk(model, x, v, t, item, plan, terms);
    } else {
      forces_stage1_bending(model, -1 - item, plan, f);
    }
  }, plan.stage1_cost.data());
}

void forces_stage2(const Model& model, const Vec3List& v, int block, const ForcePlan& plan,
                   Vec3List& f, ForceTerms terms) {
  const int first = plan.block_begin(block), end = plan.block_end(block);
  if (!model.bending) std::fill(f.begin() + first, f.begin() + end, Vec3::Zero());
  for (int k = plan.block_chunk_start[block]; k < plan.block_chunk_start[block + 1]; ++k) {
    const ForcePlan::Chunk& c = plan.chunks[plan.block_chunks[k]];
    const int lo = std::max(first, c.first_vertex), hi = std::min(end, c.end_vertex);
    for (int i = lo; i < hi; ++i) f[i] += plan.partial[c.offset + (i - c.first_vertex)];
  }
  const VertexForces out = VertexForces::of(f);
  if (model.gravity) add_gravity(model, *model.gravity, first, end, out);
  if (model.air_damping && terms == ForceTerms::All) {
    add_air_damping(model, *model.air_damping, v, first, end, out);
  }
}

void compute_forces(const Model& model, const Vec3List& x, const Vec3List& v, double t,
                    Vec3List& f, ForcePlan& plan, int threads, ForceTerms terms) {
  f.resize(x.size());
  plan.plan(model);
  forces_stage1(model, x, v, t, threads, plan, f, terms);
  parallel_for(threads, plan.num_blocks(),
               [&](int block) { forces_stage2(model, v, block, plan, f, terms); });
}

}  // namespace tissu
