// The two outputs every force term writes (membrane, bending, gravity, air damping, wind):
// forces into a VertexForces, and, for the implicit integrators, the weighted Jacobian
// c_x df/dx + c_v df/dv into a JacobianSink. Each term lives in a file of its own.
#pragma once

#include "core/types.h"

namespace tissu {

// Forces on a range of vertices, N: entry i - first_vertex for vertex i. A term adds to it
// over the whole mesh (first_vertex = 0) or over a chunk of triangles whose vertices
// start at first_vertex.
struct VertexForces {
  Vec3* data = nullptr;
  int first_vertex = 0;

  Vec3& operator[](int vertex) const { return data[vertex - first_vertex]; }
  static VertexForces of(Vec3List& f) { return {f.data(), 0}; }
};

// Receives Jacobian blocks weighted as c_x df_i/dx_j + c_v df_i/dv_j (3x3; N/m times c_x,
// N*s/m times c_v). A term adds each block once with both weights applied; a term whose
// force does not depend on x (or v) skips that part.
class JacobianSink {
 public:
  JacobianSink(double cx, double cv) : cx(cx), cv(cv) {}
  virtual ~JacobianSink() = default;

  const double cx;  // weight of df/dx
  const double cv;  // weight of df/dv

  // The nine blocks of triangle t: blocks[3 a + b] couples corner a (row) with corner b.
  virtual void add_triangle(int t, const Tri& tri, const Mat3* blocks) = 0;
  // One block at (row vertex i, column vertex j).
  virtual void add(int i, int j, const Mat3& block) = 0;
  // s I at (i, j): a block that couples each coordinate only with itself.
  virtual void add_identity(int i, int j, double s) { add(i, j, s * Mat3::Identity()); }
};

}  // namespace tissu
