// The force pipeline: the sum of the force terms the scene declared. A term the scene does
// not declare is skipped here and costs nothing.
#pragma once

#include <algorithm>
#include <vector>

#include "core/types.h"
#include "physics/block_triplets.h"
#include "physics/model.h"

namespace tissu {

// Forces are summed in an order fixed by the mesh alone, so they come out as the same bits
// on any number of threads:
//   1. triangle chunks (chunk_triangles(T) each): each chunk sums its membrane and wind
//      forces into its own buffer, which covers only the vertices its triangles touch;
//      vertex blocks (kVerticesPerBlock each): bending, each vertex from its row of Q;
//   2. vertex blocks: each vertex adds the chunk buffers in chunk order, gravity and air
//      damping.
// The items of each stage are independent; the stages run one after the other.
struct ChunkedForces {
  // Triangles per chunk: at least kMinChunkTriangles, and at most kMaxChunks chunks, so
  // that the buffers of large meshes stay close to one entry per vertex (they overlap by
  // about a row of vertices per chunk).
  static constexpr int kMinChunkTriangles = 256;
  static constexpr int kMaxChunks = 32;
  static int chunk_triangles(int triangles) {
    return std::max(kMinChunkTriangles, (triangles + kMaxChunks - 1) / kMaxChunks);
  }
  static constexpr int kVerticesPerBlock = 128;
  struct Chunk {
    int first_triangle = 0, end_triangle = 0;
    int first_vertex = 0, end_vertex = 0;  // the vertices its triangles touch
    size_t offset = 0;                     // of its buffer in `partial`
  };
  std::vector<Chunk> chunks;
  int num_vertices = 0;
  int num_triangles = 0;
  Vec3List partial;  // the chunks' buffers, back to back, N
  Vec3 origin = Vec3::Zero();  // bending's reference point for this evaluation, m

  // Plans for `model` unless already planned for it (same mesh_id, triangle array, sizes
  // and terms). Throws std::invalid_argument when the bending model does not fit the mesh.
  void plan(const Model& model);
  int num_blocks() const {
    return (num_vertices + kVerticesPerBlock - 1) / kVerticesPerBlock;
  }
  int block_begin(int b) const { return b * kVerticesPerBlock; }
  int block_end(int b) const { return std::min(num_vertices, (b + 1) * kVerticesPerBlock); }
  int num_chunks() const { return static_cast<int>(chunks.size()); }
  // Stage 1's items in the order of the vertices they touch: >= 0 a chunk, < 0 the bending
  // block -1 - item. A thread takes a contiguous share, so its chunks and its bending
  // blocks cover about the same vertices (and stage 2's blocks of the same share too).
  std::vector<int> stage1_items;
  std::vector<double> stage1_cost;  // estimated cost of each item (relative units)
  // The chunks whose vertices overlap vertex block b, in chunk order:
  // block_chunks[block_chunk_start[b] .. block_chunk_start[b + 1]).
  std::vector<int> block_chunk_start, block_chunks;
  bool bending = false;  // stage1_items include the bending blocks
  const Tri* planned_triangles = nullptr;  // the triangle array planned for
  uint64_t planned_mesh = 0;               // and its Model::mesh_id
};

// Stage 1 (see ChunkedForces), on at most `threads` threads: the membrane and wind forces
// of every triangle chunk into its buffer; the bending forces of every vertex block,
// written to f (without bending, stage 2 starts from zero instead). Call
// forces.plan(model) first.
void forces_stage1(const Model& model, const Vec3List& x, const Vec3List& v, double t,
                   int threads, ChunkedForces& forces, Vec3List& f);
// Stage 2 for vertex block `block`: f of its vertices becomes the total force.
void forces_stage2(const Model& model, const Vec3List& v, int block,
                   const ChunkedForces& forces, Vec3List& f);

// Threads worth using for a model's forces and explicit steps, of `requested`: handing
// work out costs a few microseconds per stage, so a mesh gets at most one thread per
// kTrianglesPerThread triangles.
constexpr int kTrianglesPerThread = 2000;
inline int force_threads(int requested, const Model& model) {
  return std::max(1, std::min(requested, model.num_triangles() / kTrianglesPerThread));
}

// f = membrane (+ bending) + gravity + air damping + wind at (x, v, t). N per vertex.
// The same bits whatever `threads` is (at most that many threads work on it).
void compute_forces(const Model& model, const Vec3List& x, const Vec3List& v, double t,
                    Vec3List& f, ChunkedForces& scratch, int threads);
// The same on the calling thread with temporary buffers.
void compute_forces(const Model& model, const Vec3List& x, const Vec3List& v, double t,
                    Vec3List& f);

// Gravity m g (N per vertex).
void add_gravity(const Model& model, const Vec3& g, Vec3List& f);
// The same for vertices [first, end).
void add_gravity(const Model& model, const Vec3& g, int first, int end, Vec3List& f);

// Viscous friction (eq. 7) per unit area: -C * lumped_area * v (N).
void add_air_damping(const Model& model, double c, const Vec3List& v, Vec3List& f);
// The same for vertices [first, end).
void add_air_damping(const Model& model, double c, const Vec3List& v, int first, int end,
                     Vec3List& f);

// Wind (eq. 8, interpreted): drag * A * ((w - v_tri) . n) n per triangle, a third per vertex.
void add_wind(const Model& model, const Wind& wind, const Vec3List& x, const Vec3List& v,
              double t, Vec3List& f);
// The same for triangles [first, end), added to out[vertex - vertex_offset].
void add_wind(const Model& model, const Wind& wind, const Vec3List& x, const Vec3List& v,
              double t, int first, int end, int vertex_offset, Vec3* out);

// Jacobians of the total force: df/dx (N/m) and df/dv (N*s/m). The wind's dependence on
// the normal's direction is left out (treated explicitly); see docs/physics.md.
void compute_force_jacobian(const Model& model, const Vec3List& x, const Vec3List& v, double t,
                            bool project_psd, BlockTriplets& dfdx, BlockTriplets& dfdv);

}  // namespace tissu
