// Does the order of vertices and triangles matter to the explicit step? The benchmark's
// 50,000-triangle sheet (step_setup.h) renumbered in several orders, each timed on one
// thread (CPU time, best of 5): the membrane kernel alone into one force array (its
// gathers and scatters), then by stage: stage 1 (zeroing the chunk buffers and the
// membrane kernel, forces_stage1), stage 2 (the per-vertex pass: the chunk buffers' sum,
// gravity, air damping, the integration and the divergence check, finish_block_simd) and
// the whole step; with the chunk buffers' entries per vertex and the bytes each stage
// moves per triangle, counted from the arrays it reads and writes.
//   ./build/bench/tissu_locality_bench [--quick] [--triangles N]
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include "physics/force_plan.h"
#include "physics/membrane_simd.h"
#include "physics/step.h"
#include "physics/step_scratch.h"
#include "physics/vertex_pass_simd.h"
#include "step_setup.h"

using namespace tissu;
using namespace tissu::bench;

namespace {

// The mesh with vertex i renamed new_id[i] and the triangles listed in `order` (corners
// keep their order, so every triangle keeps its orientation and rest data).
TriMesh renumbered(const TriMesh& mesh, const std::vector<int>& new_id,
                   const std::vector<int>& order) {
  TriMesh out = mesh;
  for (size_t i = 0; i < new_id.size(); ++i) {
    out.positions[new_id[i]] = mesh.positions[i];
    out.rest_uv[new_id[i]] = mesh.rest_uv[i];
  }
  for (size_t k = 0; k < order.size(); ++k) {
    const Tri& t = mesh.triangles[order[k]];
    out.triangles[k] = Tri(new_id[t[0]], new_id[t[1]], new_id[t[2]]);
  }
  return out;
}

std::vector<int> identity(size_t n) {
  std::vector<int> p(n);
  std::iota(p.begin(), p.end(), 0);
  return p;
}

std::vector<int> shuffled(size_t n, unsigned seed) {
  std::vector<int> p = identity(n);
  std::shuffle(p.begin(), p.end(), std::mt19937(seed));
  return p;
}

// Position of (x, y) on the Hilbert curve filling a 2^16 x 2^16 grid.
uint64_t hilbert_index(uint32_t x, uint32_t y) {
  uint64_t d = 0;
  for (uint32_t s = 1u << 15; s > 0; s >>= 1) {
    const uint32_t rx = (x & s) ? 1 : 0, ry = (y & s) ? 1 : 0;
    d += static_cast<uint64_t>(s) * s * ((3 * rx) ^ ry);
    if (ry == 0) {
      if (rx == 1) {
        x = s - 1 - x;
        y = s - 1 - y;
      }
      std::swap(x, y);
    }
  }
  return d;
}

// New vertex ids along the Hilbert curve of the rest coordinates.
std::vector<int> hilbert_ids(const TriMesh& mesh) {
  Vec2 lo = mesh.rest_uv[0], hi = lo;
  for (const Vec2& p : mesh.rest_uv) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const double scale = 65535.0 / (hi - lo).maxCoeff();
  std::vector<uint64_t> key(mesh.rest_uv.size());
  for (size_t i = 0; i < key.size(); ++i) {
    const Vec2 q = (mesh.rest_uv[i] - lo) * scale;
    key[i] = hilbert_index(static_cast<uint32_t>(q.x()), static_cast<uint32_t>(q.y()));
  }
  std::vector<int> by_key = identity(key.size());
  std::stable_sort(by_key.begin(), by_key.end(), [&](int a, int b) { return key[a] < key[b]; });
  std::vector<int> new_id(key.size());
  for (size_t k = 0; k < by_key.size(); ++k) new_id[by_key[k]] = static_cast<int>(k);
  return new_id;
}

// The triangles sorted by their smallest vertex id (then the others), as the generator
// lists them.
std::vector<int> by_smallest_vertex(const TriMesh& mesh) {
  auto key = [&](int t) {
    Tri c = mesh.triangles[t];
    std::sort(c.data(), c.data() + 3);
    return std::make_tuple(c[0], c[1], c[2]);
  };
  std::vector<int> order = identity(mesh.triangles.size());
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return key(a) < key(b); });
  return order;
}

void run(const std::string& name, const TriMesh& mesh, bool quick) {
  Setup s = make_setup(mesh);
  const int tris = s.model.num_triangles(), verts = s.model.num_vertices();
  const int calls = std::max(5, (quick ? 2'000'000 : 20'000'000) / tris);
  ForcePlan plan;
  plan.plan(s.model);
  Vec3List f(verts);
  std::vector<BlockCheck> checks(plan.num_blocks());
  const double kernel = best_seconds_per_call(
      [&] {
        std::fill(f.begin(), f.end(), Vec3::Zero());
        add_membrane_forces_simd(s.model, *s.model.membrane_layout, s.state.x, nullptr, 0,
                                 tris, VertexForces::of(f));
      },
      calls, 5);
  const double stage1 = best_seconds_per_call(
      [&] { forces_stage1(s.model, s.state.x, s.state.v, 0.0, 1, plan, f); }, calls, 5);
  const double stage2 = best_seconds_per_call(
      [&] {
        for (int b = 0; b < plan.num_blocks(); ++b) {
          checks[b] = BlockCheck{};
          finish_block_simd(s.model, plan, b, f, s.state.x, s.state.v, &checks[b]);
        }
      },
      calls, 5);
  Workspace ws;
  const double whole = best_seconds_per_call([&] { step(s.model, s.state, ws); }, calls, 5);
  // Bytes per triangle: stage 1 reads the rest data and ids (68 B per triangle) and the
  // positions (24 B per vertex), zeroes and then adds into the chunk buffers (24 B per
  // entry, written twice); stage 2 reads the buffers, reads and writes positions and
  // velocities and reads masses, inverse masses and lumped areas.
  const double per_vertex = static_cast<double>(verts) / tris;
  const double entries = static_cast<double>(plan.partial.size()) / tris;
  const double bytes1 = MembraneLayout::kBytesPerTriangle + 24 * per_vertex + 2 * 24 * entries;
  const double bytes2 = 24 * entries + (4 * 24 + 3 * 8) * per_vertex;
  std::printf("%-36s %8.2f %8.2f %8.2f %8.2f %8.2f %8.2f %8.0f %8.0f\n", name.c_str(),
              entries * tris / verts, kernel * 1e9 / tris, stage1 * 1e9 / tris, stage2 * 1e9 / tris,
              whole * 1e9 / tris, (whole - stage1 - stage2) * 1e9 / tris, bytes1, bytes2);
}

}  // namespace

int main(int argc, char** argv) {
  bool quick = false;
  int triangles = 50000;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--quick") == 0) {
      quick = true;
    } else if (std::strcmp(argv[i], "--triangles") == 0 && i + 1 < argc) {
      triangles = std::max(100, std::atoi(argv[++i]));
    } else {
      std::fprintf(stderr, "usage: tissu_locality_bench [--quick] [--triangles N]\n");
      return 2;
    }
  }
  const TriMesh mesh = generate_rectangle(1.0, 1.0, triangles, /*irregular=*/true, /*seed=*/1);
  const size_t nv = mesh.positions.size(), nt = mesh.triangles.size();
  std::printf("%zu triangles, %zu vertices; one thread, CPU time, ns per triangle per step "
              "(membrane kernel on %s)\n",
              nt, nv, membrane_simd_target());
  std::printf("%-36s %8s %8s %8s %8s %8s %8s %8s %8s\n", "order", "buf/vert", "kernel", "stage 1",
              "stage 2", "step", "rest", "B/tri 1", "B/tri 2");
  const std::vector<int> same = identity(nv);
  run("as generated (rows)", mesh, quick);
  run("triangles shuffled", renumbered(mesh, same, shuffled(nt, 3)), quick);
  const TriMesh scattered = renumbered(mesh, shuffled(nv, 4), identity(nt));
  run("vertices shuffled, triangles sorted", renumbered(scattered, same,
                                                        by_smallest_vertex(scattered)), quick);
  run("vertices and triangles shuffled", renumbered(scattered, same, shuffled(nt, 5)), quick);
  const TriMesh hilbert = renumbered(mesh, hilbert_ids(mesh), identity(nt));
  run("Hilbert vertices, triangles sorted", renumbered(hilbert, same,
                                                       by_smallest_vertex(hilbert)), quick);
  return 0;
}
