// The collision stage around the integrator: everything that is not one cloth vertex
// against an obstacle's surface (that is the obstacle query of step.cpp and contact.cpp).
//   - cloth against itself: vertex-triangle and edge-edge pairs;
//   - cloth against a mesh obstacle's own features: its vertices against cloth triangles
//     and its edges against cloth edges, with the obstacle's thickness (so neither a
//     table's edge nor a head's curve, finer than the cloth's triangles, cuts through
//     them, and cloth drawn across an edge slides over it), and cloth vertices against its
//     triangles by continuous detection only (a fast vertex cannot pass through a thin
//     part between two steps).
// It runs after the integrator, on the step's start positions x0 and its end positions
// x1 and velocities v, for explicit and implicit integrators alike (Bridson, Fedkiw &
// Anderson 2002, "Robust treatment of collisions, contact and friction for cloth
// animation"):
//   1. proximity: pairs closer than their thickness at x0 get an inelastic normal impulse
//      that stops their approach where it would bring them closer than the thickness, a
//      gentle repulsion (a tenth of the shortfall per step) when already closer, and
//      Coulomb friction from that impulse;
//   2. continuous collision detection on the straight paths x0 -> x1 (ccd.h); each
//      impact gets an inelastic impulse along its normal that leaves the pair apart at the
//      end of the step; repeated while new impacts appear;
//   3. impact zones when impulses alone do not settle (Harmon, Vouga, Tamstorf & Grinspun
//      2008, "Robust treatment of simultaneous collisions"): the impacts of a zone become
//      linear non-penetration constraints on the end positions, solved together by
//      projected Gauss-Seidel for the nearest admissible motion (mass-weighted); zones
//      merge as new impacts appear; a zone that still does not settle moves rigidly
//      (with the obstacle it touches, or with its own momentum; Provot 1997), the
//      last resort.
// Every impulse acts along the contact normal against approach (it removes kinetic
// energy) except the repulsion of pairs already closer than their thickness, at most a
// tenth of the shortfall per step; friction only slows tangential motion; nothing sticks
// without friction. Pairs that lie closer than their thickness in the rest shape of the
// cloth (neighbours in the fabric) are not repelled, only kept from crossing.
//
// Cost: pairs are watched from candidate lists built by bounding-volume hierarchies over
// regions around each vertex (its motion over the step plus a margin), reused for as
// many steps as every vertex stays in its region (so the many tiny steps of explicit
// integrators rebuild them rarely); a pair whose distance when the lists were built,
// less how far its vertices have moved since, exceeds its thickness is skipped. Such a
// pair is not even looked at again until a bound on that motion (the largest motion of
// any vertex, summed over the steps since, plus the largest within the step) may have
// used up its slack, so far pairs cost nothing per step. Self pairs are kept in an order
// of their own (by their primitive ids), the order their impulses are applied in: neither
// the broad phase that found them nor the order it found them in changes the result.
// Tested in tests/physics/cloth_contact_test.
#pragma once

#include <cstdint>
#include <memory>

#include "core/types.h"
#include "physics/model.h"

namespace tissu {

// What the stage did in one step.
struct ContactStats {
  int candidates = 0;   // primitive pairs watched
  bool rebuilt = false; // the candidate lists were rebuilt
  int calls = 0;        // times the stage ran (the implicit integrators run it again on a
                        // step they solve again)
  int builds = 0;       // times the candidate lists were built
  int64_t build_distances = 0;  // pair distances measured for those builds
  int proximities = 0;  // pairs closer than their thickness (or about to be) that got impulses
  int impacts = 0;      // collisions found by continuous detection, all rounds
  int rounds = 0;       // detection rounds
  int zones = 0;        // impact zones solved together
  int rigid_zones = 0;  // zones moved rigidly (last resort)
  int unresolved = 0;   // impacts left after everything (0 unless the stage gave up)

  // Sums, `rebuilt` if either rebuilt, the larger `candidates`, the other's `unresolved`.
  void add(const ContactStats& other);
};

// True when the model declares what the stage handles: self-collision, or a mesh obstacle.
bool needs_cloth_contact(const Model& model);

struct State;
struct Workspace;
// Runs the workspace's stage over one step (or substep) of dt from t0, from positions x0
// to `state`, and adds what it did and its processor time to ws.contact and
// ws.contact_seconds.
void run_collision_stage(const Model& model, double t0, double dt, const Vec3List& x0,
                         State& state, Workspace& ws);

class ClothContact {
 public:
  ClothContact();
  ~ClothContact();
  ClothContact(const ClothContact&) = delete;
  ClothContact& operator=(const ClothContact&) = delete;

  // One step from t0 to t0 + dt: x0 holds the positions at t0 (m), x1 and v the end
  // positions (m) and velocities (m/s) the integrator and the vertex-obstacle response
  // produced; x1 and v are changed as described above (a velocity change dv moves the
  // end position by dt dv). x0 must be free of crossings for the end to be.
  ContactStats resolve(const Model& model, double t0, double dt, const Vec3List& x0, Vec3List& x1,
                       Vec3List& v);

  // For tests: from now on the broad phase hands its pairs over in an order shuffled by
  // `seed` (0: in the order it finds them). The result must not change: the stage puts
  // the pairs in a canonical order of its own.
  void shuffle_broad_phase(uint64_t seed);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace tissu
