// The force pipeline: the sum of the force terms the scene declared (membrane, bending,
// gravity, air damping, wind; one file each). A term the scene does not declare is skipped
// and costs nothing.
#pragma once

#include <algorithm>

#include "core/types.h"
#include "physics/block_triplets.h"
#include "physics/force_term.h"
#include "physics/model.h"
#include "physics/workspace.h"

namespace tissu {

// Threads worth using for a model's forces and explicit steps, of `requested`: handing
// work out costs a few microseconds per stage, so a mesh gets at most one thread per
// kTrianglesPerThread triangles.
constexpr int kTrianglesPerThread = 2000;
inline int force_threads(int requested, const Model& model) {
  return std::max(1, std::min(requested, model.num_triangles() / kTrianglesPerThread));
}

// f = membrane (+ bending) + gravity + air damping + wind at (x, v, t), N per vertex, on
// the workspace's threads and with its buffers. The same bits whatever ws.threads is.
void compute_forces(const Model& model, const Vec3List& x, const Vec3List& v, double t,
                    Vec3List& f, Workspace& ws);
// The same on the calling thread with temporary buffers.
void compute_forces(const Model& model, const Vec3List& x, const Vec3List& v, double t,
                    Vec3List& f);

// The weighted Jacobian sink.cx df/dx + sink.cv df/dv of every declared term at (x, v, t).
// With `project_psd` it is the implicit solver's symmetric approximation: the membrane's
// stress term projected to be positive semi-definite, the wind's position derivative left
// out (treated explicitly); see docs/implicit.md.
void add_force_jacobian(const Model& model, const Vec3List& x, const Vec3List& v, double t,
                        bool project_psd, JacobianSink& sink);

// df/dx (N/m) and df/dv (N*s/m) as block triplets, for tests and checks.
void compute_force_jacobian(const Model& model, const Vec3List& x, const Vec3List& v, double t,
                            bool project_psd, BlockTriplets& dfdx, BlockTriplets& dfdv);

}  // namespace tissu
