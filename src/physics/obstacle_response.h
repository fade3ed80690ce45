// The response of free vertices to sphere, cylinder, plane and mesh obstacles (section
// 2.3, with the projection corrected in notes.md): the collision stage of a step.
#pragma once

#include <cstdint>
#include <vector>

#include "core/types.h"
#include "physics/obstacle.h"

namespace tissu {

// How the collision stage treats a vertex closer to an obstacle than its thickness.
struct CollisionResponse {
  double tolerance = 0.0;  // m: shortfalls up to this are left alone
  bool friction = true;    // Coulomb friction from the removed normal velocity
  // s: the weight of the step's new velocity in its new position (x_{n+1} = x_n + h
  // v_{n+1}: h for symplectic Euler and the paper's scheme). Friction that changes the
  // tangential velocity by dv also moves the position by position_weight dv, as if the step
  // had moved with the velocity friction leaves: a vertex that sticks stays where it was.
  double position_weight = 0.0;
};

// After an explicit step: section 2.3 with the projection corrected (notes.md); the
// step's own response (explicit_response) also gives friction's change to the position.
constexpr CollisionResponse kExplicitResponse{0.0, true};
// After an implicit step, which kept its contacts on their tangent planes: only a vertex
// its contact passes left inside is moved out (without friction, which the solve applies).
constexpr CollisionResponse kImplicitResponse{1e-9, false};

// For one vertex at x (m) with velocity v (m/s): closer to an obstacle than its thickness,
// it moves out to that distance along the normal at the closest surface point; the inward
// normal velocity relative to the obstacle is removed and (with friction) Coulomb friction
// slows the tangential velocity by mu * |removed normal part| (and moves x by
// response.position_weight times that change). Overlapping obstacles:
// repeated until it is clear of all (at most four passes). Returns the work per unit mass
// the obstacles' motion did on the vertex, m^2/s^2: each velocity change dotted with the
// velocity of the surface that made it (0 where no obstacle moves).
double collide_vertex(const std::vector<PlacedObstacle>& obstacles, CollisionResponse response,
                      Vec3& x, Vec3& v);

// collide_vertex on the free vertices of [first, end) (pinned: (V) 1 = pinned) that the
// vectorised near-test (obstacle_simd.h) selects; the others are farther than the
// thickness from every obstacle, which collide_vertex would leave alone. The same bits
// as collide_vertex on every free vertex, on any vector width. Returns the work the
// obstacles' motion did on those vertices (masses in kg), J.
double collide_block(const std::vector<PlacedObstacle>& obstacles, CollisionResponse response,
                     const std::vector<uint8_t>& pinned, const std::vector<double>& mass,
                     int first, int end, Vec3List& x, Vec3List& v);

}  // namespace tissu
