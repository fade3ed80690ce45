// Helpers for the strips hung over obstacles (capstan_test.cpp, edge_friction_test.cpp) and
// the box meshes the cloth meets (cloth_contact_test.cpp, mesh_barrier_test.cpp).
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "collision/closed_surface.h"
#include "collision/test_surfaces.h"
#include "physics/step.h"
#include "test_meshes.h"

namespace tissu::testing {

// How far (m) the sheet's lowest vertex at the start goes down in `seconds`, stepped at
// the model's dt; every step must succeed.
inline double lowest_vertex_drop(Sheet& s, double seconds) {
  int lowest = 0;
  for (size_t i = 0; i < s.state.x.size(); ++i) {
    if (s.state.x[i].z() < s.state.x[lowest].z()) lowest = static_cast<int>(i);
  }
  const double start = s.state.x[lowest].z();
  Workspace ws;
  const int steps = static_cast<int>(std::round(seconds / s.model.dt));
  for (int k = 0; k < steps; ++k) {
    const auto failure = step(s.model, s.state, ws);
    EXPECT_FALSE(failure.has_value()) << "step " << k;
    if (failure) break;
  }
  return start - s.state.x[lowest].z();
}

// A box from lo to hi (m) given as a triangle mesh obstacle, its thickness (m) and friction.
inline Obstacle mesh_box(const Vec3& lo, const Vec3& hi, double thickness, double friction) {
  const SurfaceData b = box_surface(lo, hi);
  Obstacle box;
  box.kind = ObstacleKind::Mesh;
  box.surface = std::make_shared<const ClosedSurface>(b.vertices, b.triangles, "box");
  box.center = box.surface->bounds().center();
  box.thickness = thickness;
  box.friction = friction;
  return box;
}

}  // namespace tissu::testing
