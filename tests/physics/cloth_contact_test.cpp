// The collision stage (cloth_contact.h): stacked layers rest at the thickness, a fast
// layer does not pass through another, the response never adds energy, layers slide
// without friction and decelerate at mu g with it, and no frame of any of these crosses
// (exact check).
#include <gtest/gtest.h>

#include <random>

#include "collision/closed_surface.h"
#include "collision/primitive_distance.h"
#include "collision/crossings.h"
#include "collision/test_surfaces.h"
#include "physics/barrier_contact.h"
#include "physics/bending.h"
#include "physics/cloth_contact.h"
#include "physics/diagnostics.h"
#include "physics/membrane.h"
#include "physics/step.h"
#include "physics/step_scratch.h"
#include "strip_checks.h"
#include "test_meshes.h"

namespace tissu {
namespace {

// Appends sheet `b` (its own vertices) to model `a` at height z, offset by `shift`, its rest
// coordinates moved `apart` (m) along u.
void append_sheet(Model& a, Vec3List& xa, const Model& b, const Vec3List& xb, const Vec3& shift,
                  double apart = 10.0) {
  const int base = static_cast<int>(a.rest_uv.size());
  for (size_t i = 0; i < b.rest_uv.size(); ++i) {
    // Rest coordinates far apart in (u, v): the sheets are separate pieces of fabric.
    a.rest_uv.push_back(b.rest_uv[i] + Vec2(apart, 0.0));
    xa.push_back(xb[i] + shift);
  }
  for (const Tri& t : b.triangles) a.triangles.push_back(t + Tri::Constant(base));
}

Obstacle ground() {
  Obstacle o;
  o.kind = ObstacleKind::Plane;
  o.center = Vec3::Zero();
  o.axis = Vec3::UnitZ();
  return o;
}

// The sheets of a stack: two different jittered grids, the upper shifted across, or the
// same regular grid twice, every edge of the upper over its twin in the lower.
enum class Layers { Jittered, Identical };

// Two w x w sheets of n x n cells, the second `gap` above the first, at height z.
Model two_sheets(double w, int n, double z, double gap, Vec3List* x,
                 Layers layers = Layers::Jittered) {
  const bool identical = layers == Layers::Identical;
  const double jitter = identical ? 0.0 : 0.3;
  Vec3List lower, upper;
  Model m = testing::grid_model(w, w, n, n, jitter, identical ? 1 : 3, &lower);
  const Model top = testing::grid_model(w, w, n, n, jitter, identical ? 1 : 4, &upper);
  for (Vec3& p : lower) p.z() = z;
  *x = lower;
  const Vec3 across = identical ? Vec3::Zero() : Vec3(0.01, -0.02, 0.0);
  append_sheet(m, *x, top, upper, across + Vec3(0, 0, z + gap));
  m.material = testing::test_material();
  m.material.damping = 1e-5;
  return m;
}

bool crosses(const Model& m, const Vec3List& x) { return self_crossings(x, m.triangles, 1).any(); }

// Two 30 cm sheets `gap` (m) apart, the lower at height z (m) above the ground, under
// gravity with air damping, layers `thickness` (m) apart with friction 0.3, on ground with
// friction 0.5, stepped by `integrator` at dt (s) with `contact`.
Model stack_over_ground(double z, double gap, double thickness, Integrator integrator, double dt,
                        ContactModel contact, Vec3List* x, Layers layers = Layers::Jittered) {
  Model m = two_sheets(0.3, 8, z, gap, x, layers);
  m.gravity = Vec3(0, 0, -9.81);
  m.air_damping = 0.5;
  m.integrator = integrator;
  m.dt = dt;
  m.implicit.contact = contact;
  m.obstacles = {ground()};
  m.obstacles[0].friction = 0.5;
  m.self_collision = SelfCollision{thickness, 0.3};
  precompute_rest(m);
  return m;
}

// The stack 4 cm apart, the lower sheet 3 cm above the ground: it falls onto it.
Model falling_stack(double thickness, Integrator integrator, double dt, ContactModel contact,
                    Vec3List* x) {
  return stack_over_ground(0.03, 0.04, thickness, integrator, dt, contact, x);
}

TEST(ClothContact, StackedSheetsRestAsTwoLayersSeparatedByTheThickness) {
  constexpr double kThickness = 0.005;  // m
  Vec3List x;
  const Model m =
      falling_stack(kThickness, Integrator::SymplecticEuler, 1e-4, ContactModel::Constraints, &x);
  State s;
  s.x = x;
  s.v.assign(x.size(), Vec3::Zero());
  Workspace ws;
  const int half = static_cast<int>(x.size()) / 2;
  for (int k = 0; k < 12000; ++k) {  // 1.2 s
    ASSERT_FALSE(step(m, s, ws).has_value()) << k;
    if (k % 200 == 0) {
      ASSERT_FALSE(crosses(m, s.x)) << "step " << k;
    }
  }
  double top_min = INFINITY, top_max = -INFINITY, top_sum = 0;
  // The lower sheet lies on the ground, never pushed into it by the one above.
  for (int i = 0; i < half; ++i) EXPECT_NEAR(s.x[i].z(), 0.0, 1e-9) << i;
  for (int i = half; i < static_cast<int>(x.size()); ++i) {
    top_min = std::min(top_min, s.x[i].z());
    top_max = std::max(top_max, s.x[i].z());
    top_sum += s.x[i].z();
  }
  // The upper sheet stops where its vertices and edges are one thickness from the lower
  // sheet: on a flat lower sheet, at z = thickness.
  EXPECT_GE(top_min, 0.95 * kThickness);
  EXPECT_LE(top_max, 1.05 * kThickness);
  EXPECT_NEAR(top_sum / half, kThickness, 0.02 * kThickness);
  double fastest = 0;
  for (const Vec3& v : s.v) fastest = std::max(fastest, v.norm());
  EXPECT_LT(fastest, 1e-3);  // at rest: no jitter between the layers
}

// The same stack with backward Euler at 1/60 s: the self barrier holds the layers apart
// inside the solve (self_barrier.h) with either contact model for the ground, so no frame
// crosses and the collision stage after the solve finds nothing to correct. The upper
// layer rests above the lower at a gap the barrier holds: between the thickness and the
// thickness plus dhat. The lower rests on the ground where the ground's model holds it:
// on it under the constraints, within dhat of it under the barrier.
void expect_stack_rests_as_two_layers_implicit(ContactModel contact) {
  constexpr double kThickness = 0.005;  // m
  Vec3List x;
  const Model m = falling_stack(kThickness, Integrator::BackwardEuler, 1.0 / 60.0, contact, &x);
  const double dhat = barrier_distance(m);
  State s;
  s.x = x;
  s.v.assign(x.size(), Vec3::Zero());
  Workspace ws;
  int corrections = 0;
  for (int k = 0; k < 72; ++k) {  // 1.2 s
    ASSERT_FALSE(step(m, s, ws).has_value()) << k;
    corrections += ws.contact.proximities + ws.contact.impacts;
    ASSERT_FALSE(crosses(m, s.x)) << "step " << k;
  }
  EXPECT_EQ(corrections, 0);
  EXPECT_GT(ws.barrier_pairs, 0);  // the layers touch within dhat at the end
  const int half = static_cast<int>(x.size()) / 2;
  double lower_mean = 0, upper_mean = 0, upper_min = INFINITY;
  for (int i = 0; i < half; ++i) {
    if (contact == ContactModel::Barrier) {
      EXPECT_GT(s.x[i].z(), 0.0) << i;
      EXPECT_LT(s.x[i].z(), dhat) << i;
    } else {
      EXPECT_NEAR(s.x[i].z(), 0.0, 1e-6) << i;
    }
    lower_mean += s.x[i].z() / half;
  }
  for (int i = half; i < static_cast<int>(x.size()); ++i) {
    upper_mean += s.x[i].z() / half;
    upper_min = std::min(upper_min, s.x[i].z());
  }
  std::printf("  dhat %.3g m; lower layer at %.3g m, upper at %.3g m (lowest %.3g)\n", dhat,
              lower_mean, upper_mean, upper_min);
  EXPECT_GT(upper_min - lower_mean, kThickness);
  EXPECT_LT(upper_mean - lower_mean, kThickness + dhat);
  double fastest = 0;
  for (const Vec3& v : s.v) fastest = std::max(fastest, v.norm());
  EXPECT_LT(fastest, 1e-3);  // at rest
}

TEST(ClothContact, StackedSheetsRestAsTwoLayersWithTheBarrier) {
  expect_stack_rests_as_two_layers_implicit(ContactModel::Barrier);
}

TEST(ClothContact, StackedSheetsRestAsTwoLayersImplicitOnAConstrainedGround) {
  expect_stack_rests_as_two_layers_implicit(ContactModel::Constraints);
}

// Two identical regular sheets laid one over the other, 1 mm beyond the thickness: every
// edge of the upper lies parallel over one of the lower, where an edge-edge pair's closest
// points jump along the edges with the least turn. The mollifier (pair_gap.h) takes those
// pairs' barrier smoothly to zero, and the stack falls and settles on the ground in a few
// Newton iterations a step, with either contact model for the ground. Without it the line
// search cut each direction to an eighth and Newton ran to its limit in every substep.
void expect_parallel_grids_settle(ContactModel contact) {
  constexpr double kThickness = 0.005;  // m
  Vec3List x;
  const Model m = stack_over_ground(0.03, kThickness + 0.001, kThickness,
                                    Integrator::BackwardEuler, 1.0 / 60.0, contact, &x,
                                    Layers::Identical);
  State s;
  s.x = x;
  s.v.assign(x.size(), Vec3::Zero());
  prepare_start(m, s);
  Workspace ws;
  int newton = 0;
  constexpr int kSteps = 30;  // 0.5 s
  for (int k = 0; k < kSteps; ++k) {
    ASSERT_FALSE(step(m, s, ws).has_value()) << k;
    newton += ws.newton_iterations;
    ASSERT_FALSE(crosses(m, s.x)) << "step " << k;
  }
  std::printf("  %d Newton iterations over %d steps\n", newton, kSteps);
  EXPECT_LE(newton, 5 * kSteps);
  const int half = static_cast<int>(x.size()) / 2;
  double lower_mean = 0, upper_mean = 0;
  for (int i = 0; i < half; ++i) lower_mean += s.x[i].z() / half;
  for (int i = half; i < 2 * half; ++i) upper_mean += s.x[i].z() / half;
  EXPECT_LT(lower_mean, barrier_distance(m));  // landed
  EXPECT_GT(upper_mean - lower_mean, kThickness);
  EXPECT_LT(upper_mean - lower_mean, kThickness + barrier_distance(m));
}

TEST(ClothContact, IdenticalGridsLaidParallelSettleInFewNewtonIterations) {
  expect_parallel_grids_settle(ContactModel::Barrier);
}

TEST(ClothContact, IdenticalGridsLaidParallelSettleInFewNewtonIterationsOnAConstrainedGround) {
  expect_parallel_grids_settle(ContactModel::Constraints);
}

// The stack of two sheets laid on the ground instead of dropped: the upper 1 mm beyond the
// thickness above the lower, within the self barrier's dhat (10.9 mm). At the start the
// layers are opened to dhat by position (separate_laid_layers), so no step throws them
// apart: the upper layer never rises more than dhat above where it was laid, and it comes
// to rest on the lower as the dropped stack does. Before that start, the first step threw
// it up at 2.7 m/s to 20 cm above the ground.
void expect_laid_stack_stays(ContactModel contact) {
  constexpr double kThickness = 0.005, kLaid = kThickness + 0.001;  // m
  Vec3List x;
  const Model m = stack_over_ground(0.0, kLaid, kThickness, Integrator::BackwardEuler,
                                    1.0 / 60.0, contact, &x);
  const double dhat = barrier_distance(m);
  State s;
  s.x = x;
  s.v.assign(x.size(), Vec3::Zero());
  Workspace ws;
  const int half = static_cast<int>(x.size()) / 2;
  double highest = -INFINITY;  // m, the upper layer's mean height above the lower's
  double lower_mean = 0, upper_mean = 0;
  for (int k = 0; k < 60; ++k) {  // 1 s
    ASSERT_FALSE(step(m, s, ws).has_value()) << k;
    ASSERT_FALSE(crosses(m, s.x)) << "step " << k;
    lower_mean = upper_mean = 0;
    for (int i = 0; i < half; ++i) lower_mean += s.x[i].z() / half;
    for (int i = half; i < 2 * half; ++i) upper_mean += s.x[i].z() / half;
    highest = std::max(highest, upper_mean - lower_mean);
  }
  EXPECT_LE(highest, kLaid + dhat);
  EXPECT_GT(upper_mean - lower_mean, kThickness);
  EXPECT_LT(upper_mean - lower_mean, kThickness + dhat);
  double fastest = 0;
  for (const Vec3& v : s.v) fastest = std::max(fastest, v.norm());
  EXPECT_LT(fastest, 1e-3);  // at rest
}

TEST(ClothContact, StackedSheetsLaidWithinTheBarrierStayTogether) {
  expect_laid_stack_stays(ContactModel::Constraints);
}

TEST(ClothContact, StackedSheetsLaidWithinTheBarrierStayTogetherOnABarrierGround) {
  expect_laid_stack_stays(ContactModel::Barrier);
}

// Three sheets laid on the ground, each 1 mm beyond the thickness above the one below, and
// a free sheet hung 5.5 mm under a pinned one, 12 mm above the ground: opening the layers
// at the start moves no vertex through another layer or into the ground (the moves stop
// short of the first touch on their paths), and no step after crosses. Opened pair by
// pair without that bound, the middle layer of the three went through the top one and the
// lowest 6 cm into the ground, and the hung sheet 4 mm into it.
TEST(ClothContact, LayersLaidWithinTheBarrierOpenWithoutCrossing) {
  constexpr double kThickness = 0.005;  // m
  for (ContactModel contact : {ContactModel::Constraints, ContactModel::Barrier}) {
    for (bool hung : {false, true}) {
      SCOPED_TRACE(std::string(contact == ContactModel::Barrier ? "barrier" : "constraints") +
                   (hung ? ", hung under a pinned sheet" : ", three laid"));
      Vec3List x, third;
      Model m = stack_over_ground(hung ? 0.012 : 0.0, kThickness + (hung ? 0.0005 : 0.001),
                                  kThickness, Integrator::BackwardEuler, 1.0 / 60.0, contact, &x);
      const int per_sheet = static_cast<int>(x.size()) / 2;
      if (!hung) {
        const Model sheet = testing::grid_model(0.3, 0.3, 8, 8, 0.3, 5, &third);
        append_sheet(m, x, sheet, third, Vec3(-0.01, 0.015, 2 * (kThickness + 0.001)), 20.0);
      }
      m.pinned.assign(x.size(), 0);
      if (hung) {
        for (int i = per_sheet; i < 2 * per_sheet; ++i) m.pinned[i] = 1;
      }
      precompute_rest(m);
      ASSERT_FALSE(crosses(m, x));
      State s;
      s.x = x;
      s.v.assign(x.size(), Vec3::Zero());
      Workspace ws;
      for (int k = 0; k < 30; ++k) {
        ASSERT_FALSE(step(m, s, ws).has_value()) << k;
        ASSERT_FALSE(crosses(m, s.x)) << "step " << k;
        for (size_t i = 0; i < s.x.size(); ++i) ASSERT_GE(s.x[i].z(), -1e-9) << "step " << k;
      }
    }
  }
}

// A small sheet 4 mm above a sheet held flat, thrown down onto it at 20 m/s, stepped by
// `integrator` at dt (s); *first_upper receives the small sheet's first vertex.
struct ThrownLayer {
  Model model;
  State state;
  int first_upper = 0;
};
ThrownLayer thrown_layer(double thickness, Integrator integrator, double dt) {
  Vec3List lower, upper;
  ThrownLayer t;
  Model& m = t.model;
  m = testing::grid_model(0.3, 0.3, 10, 10, 0.3, 5, &lower);
  const Model top = testing::grid_model(0.1, 0.1, 4, 4, 0.3, 6, &upper);
  Vec3List x = lower;
  append_sheet(m, x, top, upper, Vec3(0.013, 0.007, 0.004));
  m.material = testing::test_material();
  m.integrator = integrator;
  m.dt = dt;
  m.self_collision = SelfCollision{thickness, 0.0};
  t.first_upper = static_cast<int>(lower.size());
  m.pinned.assign(x.size(), 0);
  for (int i = 0; i < t.first_upper; ++i) m.pinned[i] = 1;  // held
  precompute_rest(m);
  t.state.x = x;
  t.state.v.assign(x.size(), Vec3::Zero());
  for (size_t i = t.first_upper; i < x.size(); ++i) t.state.v[i] = Vec3(0, 0, -20.0);
  return t;
}

// At dt = 1 ms the thrown sheet would pass 2 cm in one step, ten times the thickness, and
// end below the held one (tunnelled, with no crossing left to see). The stage stops it at
// the thickness.
TEST(ClothContact, FastLayerDoesNotPassThrough) {
  constexpr double kThickness = 0.002;
  ThrownLayer t = thrown_layer(kThickness, Integrator::SymplecticEuler, 1e-3);
  const Model& m = t.model;
  State s = t.state;
  Workspace ws;
  ASSERT_FALSE(step(m, s, ws).has_value());
  EXPECT_EQ(ws.contact.unresolved, 0);
  EXPECT_FALSE(crosses(m, s.x));
  for (int i = t.first_upper; i < m.num_vertices(); ++i) {
    EXPECT_GT(s.x[i].z(), 0.99 * kThickness) << i;
  }
  // Without the stage the same step ends below the held sheet.
  Model bare = m;
  bare.self_collision.reset();
  State b = t.state;
  Workspace wb;
  step(bare, b, wb);
  EXPECT_LT(b.x[t.first_upper].z(), -0.01);
}

// The same throw with backward Euler at 1/60 s: a third of a metre per step, yet the
// line search stops every pair short of its first touch, so the layer ends above the held
// sheet with nothing left for the collision stage. The self barrier is in the solve with
// either contact model (the scene has no obstacle).
TEST(ClothContact, FastLayerDoesNotPassThroughImplicit) {
  constexpr double kThickness = 0.002;
  for (const ContactModel contact : {ContactModel::Barrier, ContactModel::Constraints}) {
    SCOPED_TRACE(contact == ContactModel::Barrier ? "barrier" : "constraints");
    ThrownLayer t = thrown_layer(kThickness, Integrator::BackwardEuler, 1.0 / 60.0);
    t.model.implicit.contact = contact;
    const Model& m = t.model;
    State& s = t.state;
    Workspace ws;
    for (int k = 0; k < 3; ++k) {
      ASSERT_FALSE(step(m, s, ws).has_value()) << k;
      EXPECT_EQ(ws.contact.proximities + ws.contact.impacts, 0) << k;
      EXPECT_FALSE(crosses(m, s.x)) << k;
      for (int i = t.first_upper; i < m.num_vertices(); ++i) {
        ASSERT_GT(s.x[i].z(), kThickness) << "step " << k << " vertex " << i;
      }
    }
  }
}

// The stage applies its impulses in the order of its pair lists, each seeing the
// velocities the ones before it left; the lists are put in an order of their own, so the
// order in which the broad phase finds the pairs changes nothing: a sheet sliding onto
// another on the ground (thousands of impulses on pairs that share vertices) ends with
// the same bits whether the broad phase's pairs come as found or shuffled.
TEST(ClothContact, ResultDoesNotDependOnTheBroadPhaseOrder) {
  Vec3List x;
  Model m = two_sheets(0.3, 8, 0.0, 0.01, &x);
  m.gravity = Vec3(0, 0, -9.81);
  m.integrator = Integrator::SymplecticEuler;
  m.dt = 1e-4;
  m.obstacles = {ground()};
  m.obstacles[0].friction = 0.5;
  m.self_collision = SelfCollision{0.005, 0.3};
  precompute_rest(m);
  const int half = static_cast<int>(x.size()) / 2;
  auto run = [&](uint64_t seed, ContactStats* total) {
    State s;
    s.x = x;
    s.v.assign(x.size(), Vec3::Zero());
    for (int i = half; i < static_cast<int>(x.size()); ++i) s.v[i] = Vec3(0.4, 0.1, 0.0);
    Workspace ws;
    auto stage = std::make_shared<ClothContact>();
    stage->shuffle_broad_phase(seed);
    scratch_of(ws).contact = stage;
    for (int k = 0; k < 2500; ++k) {
      EXPECT_FALSE(step(m, s, ws).has_value()) << k;
      total->add(ws.contact);
    }
    return s;
  };
  ContactStats as_found;
  const State a = run(0, &as_found);
  EXPECT_GT(as_found.builds, 1);
  EXPECT_GT(as_found.proximities, 1000);
  EXPECT_FALSE(crosses(m, a.x));
  for (uint64_t seed : {1u, 2u}) {
    ContactStats shuffled;
    const State b = run(seed, &shuffled);
    EXPECT_EQ(shuffled.proximities, as_found.proximities) << seed;
    EXPECT_EQ(shuffled.impacts, as_found.impacts) << seed;
    int differ = 0;
    for (size_t i = 0; i < x.size(); ++i) differ += a.x[i] != b.x[i] || a.v[i] != b.v[i];
    EXPECT_EQ(differ, 0) << "seed " << seed;
  }
}

// End positions moved through another layer with no velocity to show it (as a position
// correction or an obstacle's projection can): only continuous detection sees it.
TEST(ClothContact, ContinuousDetectionCatchesWhatVelocitiesHide) {
  Vec3List x;
  Model m = two_sheets(0.2, 6, 0.0, 0.004, &x);
  m.self_collision = SelfCollision{0.002, 0.0};
  precompute_rest(m);
  const int half = static_cast<int>(x.size()) / 2;
  Vec3List x1 = x, v(x.size(), Vec3::Zero());
  for (int i = half; i < static_cast<int>(x.size()); ++i) x1[i].z() -= 0.01;
  ClothContact stage;
  const ContactStats stats = stage.resolve(m, 0.0, 1e-3, x, x1, v);
  EXPECT_GT(stats.impacts, 0);
  EXPECT_EQ(stats.unresolved, 0);
  EXPECT_FALSE(crosses(m, x1));
  // Wherever the sheet that moved lies over the other, it ends above it, as it started.
  int over = 0;
  for (int i = half; i < static_cast<int>(x.size()); ++i) {
    for (int t = 0; t < static_cast<int>(m.triangles.size()) / 2; ++t) {
      const Tri& tri = m.triangles[t];
      const Vec2 a = x1[tri[0]].head<2>(), b = x1[tri[1]].head<2>(), c = x1[tri[2]].head<2>();
      const Vec2 p = x1[i].head<2>();
      Eigen::Matrix2d e;
      e << b - a, c - a;
      const Vec2 w = e.inverse() * (p - a);
      if (w.minCoeff() < 0 || w.sum() > 1) continue;
      const double below = x1[tri[0]].z() + w[0] * (x1[tri[1]].z() - x1[tri[0]].z()) +
                           w[1] * (x1[tri[2]].z() - x1[tri[0]].z());
      EXPECT_GT(x1[i].z(), below) << i;
      ++over;
      break;
    }
  }
  EXPECT_GT(over, half / 3);
}

// Random approaching layers, all pairs farther apart than the thickness at the start:
// every impulse stops approach (and friction slows sliding), so kinetic energy can only
// fall; and nothing crosses at the end.
TEST(ClothContact, ResponseNeverAddsEnergy) {
  for (unsigned seed = 1; seed <= 6; ++seed) {
    Vec3List x;
    Model m = two_sheets(0.2, 6, 0.0, 0.01, &x);
    m.self_collision = SelfCollision{0.003, seed % 2 ? 0.4 : 0.0};
    precompute_rest(m);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1, 1);
    Vec3List v(x.size());
    const int half = static_cast<int>(x.size()) / 2;
    for (int i = 0; i < static_cast<int>(x.size()); ++i) {
      v[i] = Vec3(u(rng), u(rng), u(rng)) + Vec3(0, 0, i < half ? 3.0 : -3.0);
    }
    const double dt = 5e-3;  // the layers would pass 2 cm into each other
    Vec3List x1(x.size());
    for (size_t i = 0; i < x.size(); ++i) x1[i] = x[i] + dt * v[i];
    const double before = kinetic_energy(m, v);
    ClothContact stage;
    const ContactStats stats = stage.resolve(m, 0.0, dt, x, x1, v);
    EXPECT_GT(stats.impacts + stats.proximities, 0);
    EXPECT_EQ(stats.unresolved, 0);
    EXPECT_LE(kinetic_energy(m, v), before * (1 + 1e-12)) << "seed " << seed;
    EXPECT_FALSE(crosses(m, x1)) << "seed " << seed;
    for (size_t i = 0; i < x.size(); ++i) {
      EXPECT_TRUE((x1[i] - x[i] - dt * v[i]).norm() < 1e-12) << "end position follows the velocity";
    }
  }
}

// A triangle held level at z = 0 and a small triangle above it pointing one corner down
// at height `height`: two pieces of fabric (apart at rest).
Model vertex_over_triangle(double height, Vec3List* x) {
  Model m;
  m.rest_uv = {Vec2(-0.1, -0.1), Vec2(0.1, -0.1), Vec2(0.0, 0.1),
               Vec2(10.0, 0.0), Vec2(10.05, 0.05), Vec2(9.95, 0.05)};
  m.triangles = {Tri(0, 1, 2), Tri(3, 4, 5)};
  *x = {Vec3(-0.1, -0.1, 0.0), Vec3(0.1, -0.1, 0.0), Vec3(0.0, 0.1, 0.0),
        Vec3(0.0, 0.0, height), Vec3(0.05, 0.05, height + 0.05), Vec3(-0.05, 0.05, height + 0.05)};
  m.material = testing::test_material();
  return m;
}

double corner_to_triangle(const Vec3List& x) {
  return (x[3] - closest_on_triangle(x[3], x[0], x[1], x[2]).point).norm();
}

// The stage looks at a watched pair again only when a bound on how far its points may
// have moved says it may be near (cloth_contact.cpp, `scheduled`). Here that bound is as
// tight as it gets: the triangle rises and the corner falls, every vertex at the same
// speed u (the cloth's mean motion is zero), so the pair's slack shrinks by 2 u dt a
// step, as fast as the bound allows. The start is set so that the pair comes within the
// thickness in step 40, a tenth of a step's approach before it: looked at one step late,
// the corner would end 0.9 * 2 u dt (a third of the thickness) inside it.
TEST(ClothContact, PairsApproachingAtTheBoundsSpeedAreCaughtInTime) {
  constexpr double kThickness = 0.002, kDt = 1e-3, kSpeed = 0.3;  // m, s, m/s
  const double approach = 2.0 * kSpeed * kDt;                     // m per step
  Vec3List x;
  Model m = vertex_over_triangle(kThickness + 40.1 * approach, &x);
  m.self_collision = SelfCollision{kThickness, 0.0};
  precompute_rest(m);
  Vec3List v(6);
  for (int i = 0; i < 6; ++i) v[i] = Vec3(0, 0, i < 3 ? kSpeed : -kSpeed);
  ClothContact stage;
  int rebuilds = 0, first_response = -1;
  for (int k = 0; k < 80; ++k) {
    Vec3List x1(6);
    for (int i = 0; i < 6; ++i) x1[i] = x[i] + kDt * v[i];
    const ContactStats stats = stage.resolve(m, k * kDt, kDt, x, x1, v);
    rebuilds += stats.rebuilt;
    if (stats.proximities > 0 && first_response < 0) first_response = k;
    x = x1;
    ASSERT_GE(corner_to_triangle(x), 0.99 * kThickness) << "step " << k;
    ASSERT_FALSE(crosses(m, x)) << "step " << k;
  }
  EXPECT_EQ(first_response, 40);
  EXPECT_EQ(rebuilds, 1);  // the lists of the first step served throughout
}

// The bound also counts how far a vertex may go within the step itself: here nothing
// moves for ten steps, then the corner drops 4 mm in one, from 3 mm above the thickness
// (its start has not moved, so only that term can wake the pair).
TEST(ClothContact, PairsAreCaughtWhenAVertexJumpsAfterRest) {
  constexpr double kThickness = 0.002, kDt = 1e-3, kDrop = 0.004;
  Vec3List x;
  Model m = vertex_over_triangle(kThickness + 0.003, &x);
  m.self_collision = SelfCollision{kThickness, 0.0};
  precompute_rest(m);
  ClothContact stage;
  int rebuilds = 0;
  for (int k = 0; k < 12; ++k) {
    Vec3List x1 = x, v(6, Vec3::Zero());
    if (k == 10) {
      v[3] = Vec3(0, 0, -kDrop / kDt);
      x1[3] += kDt * v[3];
    }
    const ContactStats stats = stage.resolve(m, k * kDt, kDt, x, x1, v);
    rebuilds += stats.rebuilt;
    if (k == 10) {
      EXPECT_GT(stats.proximities, 0);
    }
    x = x1;
    ASSERT_GE(corner_to_triangle(x), 0.99 * kThickness) << "step " << k;
  }
  EXPECT_EQ(rebuilds, 1);
}

// A sheet sliding over a sheet held flat, pressed by gravity: without friction it keeps
// its speed; with friction mu it slows by mu g (Coulomb). Symplectic Euler at 0.1 ms with
// the collision stage, or backward Euler at 1/100 s with the barrier (the sheet is laid
// within the barrier's reach, the thickness plus half of dhat above the other, which the
// run's start opens to dhat, and settles for 0.3 s before it is pushed; before that start
// the first steps threw it up to 13 cm above the other, still rising when pushed).
double slide_speed_after(double friction, double seconds, bool barrier = false) {
  constexpr double kThickness = 0.004;
  Vec3List lower, upper;
  Model m = testing::grid_model(0.8, 0.4, 16, 8, 0.3, 8, &lower);
  const Model top = testing::grid_model(0.15, 0.15, 4, 4, 0.3, 9, &upper);
  Vec3List x = lower;
  append_sheet(m, x, top, upper, Vec3(-0.2, 0.0, kThickness));
  m.material = testing::test_material();
  m.material.damping = 1e-5;
  m.gravity = Vec3(0, 0, -9.81);
  m.integrator = barrier ? Integrator::BackwardEuler : Integrator::SymplecticEuler;
  m.dt = barrier ? 0.01 : 1e-4;
  if (barrier) {
    m.implicit.contact = ContactModel::Barrier;
    precompute_rest(m);
    for (size_t i = lower.size(); i < x.size(); ++i) x[i].z() += 0.5 * barrier_distance(m);
  }
  m.self_collision = SelfCollision{kThickness, friction};
  const int first_upper = static_cast<int>(lower.size());
  m.pinned.assign(x.size(), 0);
  for (int i = 0; i < first_upper; ++i) m.pinned[i] = 1;  // held
  precompute_rest(m);
  State s;
  s.x = x;
  s.v.assign(x.size(), Vec3::Zero());
  Workspace ws;
  for (int k = 0; barrier && k < 30; ++k) EXPECT_FALSE(step(m, s, ws).has_value());
  for (int i = first_upper; i < static_cast<int>(x.size()); ++i) s.v[i] = Vec3(1.0, 0, 0);
  const int steps = static_cast<int>(std::lround(seconds / m.dt));
  for (int k = 0; k < steps; ++k) {
    EXPECT_FALSE(step(m, s, ws).has_value());
    if (barrier || k % 250 == 0) {
      EXPECT_FALSE(crosses(m, s.x)) << k;
    }
  }
  double mean = 0;
  for (int i = first_upper; i < static_cast<int>(x.size()); ++i) {
    mean += s.v[i].x();
    EXPECT_GT(s.x[i].z(), 0.9 * kThickness);
  }
  return mean / (x.size() - first_upper);
}

TEST(ClothContact, LayersSlideFreelyWithoutFriction) {
  EXPECT_NEAR(slide_speed_after(0.0, 0.2), 1.0, 0.01);
}

TEST(ClothContact, FrictionBetweenLayersSlowsByMuG) {
  const double mu = 0.3, t = 0.2;
  // Coulomb: v(t) = v0 - mu g t = 1 - 0.3 * 9.81 * 0.2 = 0.41 m/s.
  EXPECT_NEAR(slide_speed_after(mu, t), 1.0 - mu * 9.81 * t, 0.03);
}

// The same inside the implicit solve: the barrier holds the layers apart and its lagged
// friction acts on their relative velocity. Without friction the sheet loses about 1% of
// its speed in 0.2 s (0.9905 m/s): riding over the lower sheet's edges and vertices its
// pairs' gaps rise and fall, and the barrier's normal damping takes that motion's energy.
TEST(ClothContact, LayersSlideFreelyWithoutFrictionWithTheBarrier) {
  EXPECT_NEAR(slide_speed_after(0.0, 0.2, true), 1.0, 0.015);
}

TEST(ClothContact, FrictionBetweenLayersSlowsByMuGWithTheBarrier) {
  const double mu = 0.3, t = 0.2;
  EXPECT_NEAR(slide_speed_after(mu, t, true), 1.0 - mu * 9.81 * t, 0.03);
}

}  // namespace
}  // namespace tissu

namespace tissu {
namespace {

// A sheet half over the edge of a box given as a triangle mesh, without friction: the
// hanging half pulls the rest across the edge. It must neither stop at the edge (snag)
// nor pass into the box or be cut by its edge (tunnel), at 1/60 s with backward Euler.
struct EdgePull {
  std::vector<double> centroid_x;  // m, after each step
  bool crossed = false;            // a cloth triangle crossed the box's or another's
  double worst = INFINITY;         // m, closest vertex to the box surface over the run
};

EdgePull pull_over_edge(Integrator integrator, double dt, double seconds,
                        ContactModel contact = ContactModel::Constraints) {
  constexpr double kThickness = 0.003;
  Vec3List x;
  Model m = testing::grid_model(0.3, 0.2, 12, 8, 0.3, 12, &x);
  for (Vec3& p : x) p.z() = kThickness;
  m.material = testing::test_material();
  m.material.bending = 1e-5;  // N*m
  m.material.damping = 1e-4;
  m.gravity = Vec3(0, 0, -9.81);
  m.integrator = integrator;
  m.dt = dt;
  m.implicit.contact = contact;
  const Obstacle box =
      testing::mesh_box(Vec3(-0.4, -0.2, -0.3), Vec3(0.0, 0.2, 0.0), kThickness, 0.0);
  const ClosedSurface& surface = *box.surface;
  m.obstacles = {box};
  m.self_collision = SelfCollision{kThickness, 0.0};
  precompute_rest(m);
  if (m.material.bending > 0.0) {
    m.bending = std::make_shared<const BendingModel>(
        build_bending(m.triangles, m.rest_uv, m.material.bending, m.material.bending_warp));
  }
  State st;
  st.x = x;
  st.v.assign(x.size(), Vec3::Zero());
  Workspace ws;
  EdgePull r;
  const int steps = static_cast<int>(std::lround(seconds / dt));
  for (int k = 0; k < steps; ++k) {
    const auto divergence = step(m, st, ws);
    EXPECT_FALSE(divergence.has_value()) << k << ": " << (divergence ? divergence->reason : "");
    double cx = 0;
    for (const Vec3& p : st.x) {
      cx += p.x() / st.x.size();
      Vec3 n;
      r.worst = std::min(r.worst, box.signed_distance(p, st.t, &n));
    }
    r.centroid_x.push_back(cx);
    r.crossed = r.crossed || crosses(m, st.x) ||
                crossings_between(st.x, m.triangles, surface.vertices(), surface.triangles(), 1)
                    .any();
  }
  return r;
}

void expect_slides_off(const EdgePull& r, double dt) {
  EXPECT_FALSE(r.crossed);
  EXPECT_GE(r.worst, 0.003 - 1e-6);  // vertices keep the thickness
  // Once the hanging half has swung down (0.2 s), it keeps drawing the sheet across the
  // edge (the centroid advances in every tenth of a second) until the sheet has left the
  // top: no snag.
  const int tenth = static_cast<int>(std::lround(0.1 / dt));
  for (size_t k = 3 * tenth; k < r.centroid_x.size(); k += tenth) {
    if (r.centroid_x[k - tenth] > 0.15) break;  // off the top
    EXPECT_GT(r.centroid_x[k], r.centroid_x[k - tenth] + 1e-3) << "stalled at step " << k;
  }
  EXPECT_GT(r.centroid_x.back(), 0.1);
}

TEST(ClothContact, ClothPulledAcrossAMeshEdgeNeitherSnagsNorTunnelsImplicit) {
  expect_slides_off(pull_over_edge(Integrator::BackwardEuler, 1.0 / 60.0, 1.0), 1.0 / 60.0);
}

// With the barrier the box's edge meets the cloth's edges inside the solve.
TEST(ClothContact, ClothPulledAcrossAMeshEdgeNeitherSnagsNorTunnelsWithTheBarrier) {
  for (Integrator integrator : {Integrator::BackwardEuler, Integrator::Bdf2}) {
    SCOPED_TRACE(integrator_name(integrator));
    expect_slides_off(
        pull_over_edge(integrator, 1.0 / 60.0, 1.0, ContactModel::Barrier), 1.0 / 60.0);
  }
}

TEST(ClothContact, ClothPulledAcrossAMeshEdgeNeitherSnagsNorTunnelsExplicit) {
  expect_slides_off(pull_over_edge(Integrator::SymplecticEuler, 2e-4, 0.8), 2e-4);
}

// A hanging curtain that a ball pushes through at 1 m/s, with backward Euler at 1/60 s: the
// ball as an analytic sphere or as a mesh of the same radius. Returns the largest principal
// strain over the run and, through the pointers, the smallest distance of a vertex to the
// ball's surface and whether any frame crossed it.
double push_curtain(bool mesh_ball, double* closest, bool* crossed) {
  constexpr double kThickness = 0.003, kRadius = 0.12;  // m
  Vec3List uv;
  Model m = testing::grid_model(0.6, 0.6, 12, 12, 0.3, 5, &uv);
  Vec3List x(uv.size());
  m.pinned.assign(uv.size(), 0);
  for (size_t i = 0; i < uv.size(); ++i) {
    x[i] = Vec3(uv[i].x() - 0.3, 0.0, uv[i].y() + 0.1);  // the x-z plane, z from 0.1 to 0.7
    m.pinned[i] = x[i].z() > 0.7 - 1e-9;                  // held along its top edge
  }
  m.material = testing::test_material();
  m.material.damping = 1e-4;
  m.gravity = Vec3(0, 0, -9.81);
  m.integrator = Integrator::BackwardEuler;
  m.dt = 1.0 / 60.0;
  Obstacle ball;
  ball.center = Vec3(0.0, -0.2, 0.35);
  ball.radius = kRadius;
  ball.friction = 0.2;
  ball.thickness = kThickness;
  ball.motion.velocity = Vec3(0.0, 1.0, 0.0);
  testing::SurfaceData surface;
  if (mesh_ball) {
    surface = testing::icosphere(3, kRadius, ball.center);
    ball.kind = ObstacleKind::Mesh;
    ball.surface = std::make_shared<const ClosedSurface>(surface.vertices, surface.triangles, "ball");
  }
  m.obstacles = {ball};
  precompute_rest(m);
  State st;
  st.x = x;
  st.v.assign(x.size(), Vec3::Zero());
  Workspace ws;
  double strain = 0.0;
  *closest = INFINITY;
  *crossed = false;
  for (int k = 0; k < 36; ++k) {  // 0.6 s: the ball goes through and beyond
    const auto divergence = step(m, st, ws);
    EXPECT_FALSE(divergence.has_value()) << k << ": " << (divergence ? divergence->reason : "");
    strain = std::max(strain, max_principal_strain(m, st.x));
    for (const Vec3& p : st.x) {
      Vec3 n;
      *closest = std::min(*closest, m.obstacles[0].signed_distance(p, st.t, &n));
    }
    if (mesh_ball) {
      Vec3List placed = surface.vertices;
      for (Vec3& p : placed) p = m.obstacles[0].carried(p, st.t);
      *crossed = *crossed || crossings_between(st.x, m.triangles, placed, surface.triangles, 1).any();
    }
  }
  return strain;
}

// The collision stage once pushed cloth that slides over a moving mesh off its surface
// (the direction between a feature's closest points leans along the surface there), and
// the implicit solve's contacts pulled it back: the curtain stretched by tens of percent
// where the analytic ball stretches it by a few.
TEST(ClothContact, MovingMeshBallPushesACurtainAsTheAnalyticBallDoesImplicit) {
  double closest_sphere = 0.0, closest_mesh = 0.0;
  bool crossed_sphere = false, crossed_mesh = false;
  const double sphere = push_curtain(false, &closest_sphere, &crossed_sphere);
  const double mesh = push_curtain(true, &closest_mesh, &crossed_mesh);
  EXPECT_GE(closest_mesh, 0.003 - 1e-6);  // vertices keep the thickness
  EXPECT_FALSE(crossed_mesh);
  // Facets of 2-3 cm on a 12 cm ball bend the cloth more than the round surface does, by
  // a few percent of strain at most.
  EXPECT_LT(mesh, sphere + 0.05) << "analytic ball: " << sphere;
}

// A cotton sheet dropped onto a box mesh that rises at `speed` (m/s), with backward Euler
// at 1/60 s for 0.5 s and the given contact model. Returns the largest principal strain
// over the run.
double sheet_on_rising_box(double speed, ContactModel contact = ContactModel::Constraints) {
  constexpr double kThickness = 0.002;  // m
  Vec3List x;
  Model m = testing::grid_model(0.6, 0.6, 10, 10, 0.3, 1, &x);
  for (Vec3& p : x) p += Vec3(-0.3, -0.3, 0.105);
  m.material = *material_preset("cotton");
  m.gravity = Vec3(0, 0, -9.81);
  m.integrator = Integrator::BackwardEuler;
  m.dt = 1.0 / 60.0;
  m.implicit.contact = contact;
  Obstacle box;
  box.kind = ObstacleKind::Mesh;
  const testing::SurfaceData s =
      testing::box_surface(Vec3(-0.15, -0.15, -0.1), Vec3(0.15, 0.15, 0.1));
  box.surface = std::make_shared<const ClosedSurface>(s.vertices, s.triangles, "box");
  box.center = box.surface->bounds().center();
  box.thickness = kThickness;
  box.motion.velocity = Vec3(0.0, 0.0, speed);
  m.obstacles = {box};
  precompute_rest(m);
  m.bending = std::make_shared<const BendingModel>(build_bending(
      m.triangles, m.rest_uv, m.material.bending, m.material.bending_warp));
  State st;
  st.x = x;
  st.v.assign(x.size(), Vec3::Zero());
  Workspace ws;
  double strain = 0.0;
  for (int k = 0; k < 30; ++k) {
    const auto divergence = step(m, st, ws);
    EXPECT_FALSE(divergence.has_value()) << k << ": " << (divergence ? divergence->reason : "");
    if (divergence) break;
    strain = std::max(strain, max_principal_strain(m, st.x));
  }
  return strain;
}

// The stage's energy rule once stayed off while any obstacle moved: a sheet on a box
// rising at 1 cm/s stretched by 70% and one at 10 cm/s diverged, where the still box
// stretches it by 0.6%. The rule now allows what the moving box's contacts can supply
// (0.9% and 0.8%). Since the box's corners and edges meet the cloth inside the solve
// (mesh_barrier.h) the sheet stretches by 1.1%, 0.9% and 1.6%; symplectic Euler at 5e-5 s
// stretches it by 1.2%, 1.5% and 1.6% (largest strain at the 1/60 s frames).
TEST(ClothContact, SheetOnARisingMeshBoxStretchesAsOnAStillOneImplicit) {
  const double still = sheet_on_rising_box(0.0);
  EXPECT_LT(still, 0.02);
  for (const double speed : {0.01, 0.1}) {
    EXPECT_LT(sheet_on_rising_box(speed), still + 0.01) << speed << " m/s";
  }
}

// The same with the barrier, which holds the box's corners and edges inside the solve.
TEST(ClothContact, SheetOnARisingMeshBoxStretchesAsOnAStillOneWithTheBarrier) {
  const double still = sheet_on_rising_box(0.0, ContactModel::Barrier);
  EXPECT_LT(still, 0.01);
  for (const double speed : {0.01, 0.1}) {
    EXPECT_LT(sheet_on_rising_box(speed, ContactModel::Barrier), still + 0.01) << speed << " m/s";
  }
}

}  // namespace
}  // namespace tissu
