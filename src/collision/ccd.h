// Continuous collision detection between moving mesh primitives (Bridson, Fedkiw &
// Anderson 2002, section 6; Provot 1997): vertices move on straight lines from their
// positions at the start of a step to those at its end. A vertex meets a triangle, or an
// edge meets an edge, only when the four points are coplanar: the roots in [0, 1] of a
// cubic in the step fraction. Each root (and each point where the cubic touches zero
// without crossing) is checked: the primitives count as meeting there when they are closer
// than `eta` (m). Tested in tests/collision/ccd_test.
#pragma once

#include <optional>

#include "core/types.h"

namespace tissu {

// Where and how two primitives meet during a step.
struct Impact {
  double time = 0.0;  // step fraction of the first contact, in [0, 1]
  // The contact as a combination of the four points: sum_i weights[i] x_i is the vector
  // between the two closest points (zero at contact). Vertex-triangle: (1, -w_a, -w_b,
  // -w_c); edge-edge: (1 - s, s, -(1 - t), -t).
  double weights[4] = {0, 0, 0, 0};
  // Unit normal at the contact, oriented so that n . sum_i weights[i] x_i >= 0 at the
  // start of the step (the side each primitive came from).
  Vec3 normal = Vec3::UnitZ();
};

// Vertex x[0] against triangle (x[1], x[2], x[3]); start[i] at the step's start, end[i]
// at its end (m). The first contact closer than eta, or none.
std::optional<Impact> vertex_triangle_impact(const Vec3 start[4], const Vec3 end[4], double eta);

// Edge (x[0], x[1]) against edge (x[2], x[3]).
std::optional<Impact> edge_edge_impact(const Vec3 start[4], const Vec3 end[4], double eta);

// Coefficients c[0..3] of the coplanarity cubic sum_k c[k] t^k of four moving points:
// ((x1 - x0) x (x2 - x0)) . (x3 - x0) at step fraction t (m^3).
void coplanarity_cubic(const Vec3 start[4], const Vec3 end[4], double c[4]);

// The step fractions in [0, 1], ascending, where the cubic may vanish: its roots (found
// by bisection on each monotone piece) and its local extrema in [0, 1] (touching). At most
// 5 values; returns how many.
int cubic_candidate_times(const double c[4], double times[5]);

}  // namespace tissu
