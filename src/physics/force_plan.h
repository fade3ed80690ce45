// How the force terms are summed on several threads with the same bits on any thread count
// (internal to the step and the implicit solver; callers use compute_forces in forces.h).
//
// The order is fixed by the mesh alone:
//   1. triangle chunks (chunk_triangles(T) each): each chunk sums its membrane and wind
//      forces into its own buffer, which covers only the vertices its triangles touch;
//      vertex blocks (kVerticesPerBlock each): bending, each vertex from its row of Q;
//   2. vertex blocks: each vertex adds the chunk buffers in chunk order, gravity and air
//      damping.
// The items of each stage are independent; the stages run one after the other.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "core/types.h"
#include "physics/bending.h"
#include "physics/model.h"

namespace tissu {

struct ForcePlan {
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
  CenteredPositions centered;  // x - bending_origin(x), what the bending kernel reads, m

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

// Which terms an evaluation sums: all of them, or only the conservative ones (membrane
// elasticity, bending, gravity: minus the gradient of the potential energy), which the
// implicit solver's line search needs apart.
enum class ForceTerms { All, Conservative };

// Stage 1 (see ForcePlan), on at most `threads` threads: the membrane and wind forces of
// every triangle chunk into its buffer; the bending forces of every vertex block, written
// to f (without bending, stage 2 starts from zero instead). Call plan.plan(model) first.
void forces_stage1(const Model& model, const Vec3List& x, const Vec3List& v, double t,
                   int threads, ForcePlan& plan, Vec3List& f,
                   ForceTerms terms = ForceTerms::All);
// Stage 2 for vertex block `block`: f of its vertices becomes the total force.
void forces_stage2(const Model& model, const Vec3List& v, int block, const ForcePlan& plan,
                   Vec3List& f, ForceTerms terms = ForceTerms::All);

// Both stages over the whole mesh on at most `threads` threads.
void compute_forces(const Model& model, const Vec3List& x, const Vec3List& v, double t,
                    Vec3List& f, ForcePlan& plan, int threads,
                    ForceTerms terms = ForceTerms::All);

}  // namespace tissu
