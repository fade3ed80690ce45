// The barrier model of contact (barrier_contact.h): the log barrier's derivatives against
// finite differences for each obstacle kind, the line search's first touch, and sheets
// resting on a plane and dropped on a sphere, with "implicit": {"contact": "barrier"}.
// The inclines with the barrier are in contact_test.cpp, beside the constraints' ones.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>

#include "physics/barrier_contact.h"
#include "physics/diagnostics.h"
#include "physics/implicit.h"
#include "physics/step.h"
#include "physics/stepper.h"
#include "test_meshes.h"

namespace tissu {
namespace {

constexpr double kDhat = 1e-3;  // m, the derivative checks' activation distance

using testing::cotton_sheet;
using testing::Sheet;
using testing::make_obstacle;

// --- The barrier's derivatives ------------------------------------------------------------

TEST(Barrier, ScalarDerivativesMatchFiniteDifferences) {
  const double kappa = 3.0, step = 1e-9;  // kg/s^2, m
  for (double d : {1e-5, 1e-4, 3e-4, 7e-4, 9.9e-4}) {
    const double b1 = (barrier_energy(d + step, kDhat, kappa) -
                       barrier_energy(d - step, kDhat, kappa)) / (2 * step);
    const double b2 = (barrier_derivative(d + step, kDhat, kappa) -
                       barrier_derivative(d - step, kDhat, kappa)) / (2 * step);
    EXPECT_NEAR(barrier_derivative(d, kDhat, kappa), b1, 1e-5 * std::fabs(b1)) << d;
    EXPECT_NEAR(barrier_second_derivative(d, kDhat, kappa), b2, 1e-5 * std::fabs(b2)) << d;
    EXPECT_LT(barrier_derivative(d, kDhat, kappa), 0.0);       // pushes out
    EXPECT_GT(barrier_second_derivative(d, kDhat, kappa), 0.0);  // convex
  }
  // Zero with its first two derivatives at dhat (the barrier switches on smoothly), and
  // unbounded at the surface.
  EXPECT_EQ(barrier_energy(kDhat, kDhat, kappa), 0.0);
  EXPECT_NEAR(barrier_derivative(kDhat * (1 - 1e-9), kDhat, kappa), 0.0, 1e-12);
  EXPECT_TRUE(std::isinf(barrier_energy(0.0, kDhat, kappa)));
}

// holding_gap inverts the barrier's force: -b'(d) = F at the gap it returns, for loads from
// a thousandth to a thousand times kappa dhat; dhat for no load or a pull.
TEST(Barrier, HoldingGapIsWhereTheBarrierPushesWithTheLoad) {
  const double kappa = 3.0;  // kg/s^2
  for (double load : {1e-3, 0.1, 1.0, 10.0, 1e3}) {
    const double force = load * kappa * kDhat;  // N
    const double d = holding_gap(force, kDhat, kappa);
    EXPECT_GT(d, 0.0);
    EXPECT_LT(d, kDhat);
    EXPECT_NEAR(-barrier_derivative(d, kDhat, kappa), force, 1e-9 * force) << load;
  }
  EXPECT_EQ(holding_gap(0.0, kDhat, kappa), kDhat);
  EXPECT_EQ(holding_gap(-1.0, kDhat, kappa), kDhat);
}

// Points 0.1-0.9 dhat outside a sphere, the side, a cap and the rim of a capped cylinder,
// and a tilted plane, each obstacle with a thickness and moved away from its start: the
// gradient matches central differences of the energy and the exact Hessian those of the
// gradient; the projected Hessian is positive semi-definite and agrees with the exact one
// along the normal.
TEST(Barrier, GradientAndHessianMatchFiniteDifferencesForEachObstacle) {
  const double thickness = 0.002, kappa = 5.0;  // m, kg/s^2
  const Vec3 c(0.1, -0.2, 0.3);
  struct Case {
    const char* name;
    Obstacle ob;
    Vec3 direction;  // from the centre toward the point
  };
  const Vec3 axis = Vec3(0.2, 0.1, 1.0).normalized();
  const Vec3 across = axis.cross(Vec3::UnitX()).normalized();
  const Case cases[] = {
      {"sphere", make_obstacle(ObstacleKind::Sphere, c, axis, 0.1, 0, thickness),
       Vec3(0.3, -0.5, 0.8)},
      {"cylinder side", make_obstacle(ObstacleKind::Cylinder, c, axis, 0.1, 0, thickness),
       Vec3(across + 0.3 * axis)},
      {"cylinder cap", make_obstacle(ObstacleKind::Cylinder, c, axis, 0.1, 0, thickness),
       Vec3(axis + 0.2 * across)},
      {"cylinder rim", make_obstacle(ObstacleKind::Cylinder, c, axis, 0.1, 0, thickness),
       Vec3(axis + across)},
      {"plane", make_obstacle(ObstacleKind::Plane, c, axis, 0, 0, thickness), axis},
  };
  for (const Case& k : cases) {
    Obstacle ob = k.ob;
    ob.motion.velocity = Vec3(0.1, 0.0, -0.2);
    const PlacedObstacle placed = place_obstacle(ob, 0.5);
    for (double fraction : {0.1, 0.5, 0.9}) {
      SCOPED_TRACE(::testing::Message() << k.name << " at " << fraction << " dhat");
      // March out from the centre to the wanted gap (the gap is 1-Lipschitz).
      Vec3 p = placed.center + 0.05 * k.direction.normalized();
      for (int it = 0; it < 50; ++it) {
        const Gap g = obstacle_gap(placed, p);
        p += (fraction * kDhat - g.d) * g.normal;
      }
      ASSERT_NEAR(obstacle_gap(placed, p).d, fraction * kDhat, 1e-12);
      for (double out : {0.0, 0.5, 1.0, 3.0}) {  // dhat further out: the same bits
        const Vec3 q = p + out * kDhat * obstacle_gap(placed, p).normal;
        EXPECT_EQ(gap_distance(placed, q), obstacle_gap(placed, q).d);
      }
      const BarrierTerm exact = vertex_barrier(placed, p, kappa, kDhat, false);
      const BarrierTerm psd = vertex_barrier(placed, p, kappa, kDhat, true);
      const double step = 1e-8;  // m
      Mat3 fd_hessian;
      for (int a = 0; a < 3; ++a) {
        const Vec3 e = step * Vec3::Unit(a);
        const BarrierTerm plus = vertex_barrier(placed, p + e, kappa, kDhat, false);
        const BarrierTerm minus = vertex_barrier(placed, p - e, kappa, kDhat, false);
        EXPECT_NEAR(exact.gradient[a], (plus.energy - minus.energy) / (2 * step),
                    1e-6 * exact.gradient.norm());
        fd_hessian.col(a) = (plus.gradient - minus.gradient) / (2 * step);
      }
      EXPECT_LT((exact.hessian - fd_hessian).norm(), 1e-5 * exact.hessian.norm());
      EXPECT_LT((exact.hessian - exact.hessian.transpose()).norm(), 1e-12 * exact.hessian.norm());
      const Eigen::SelfAdjointEigenSolver<Mat3> eig(psd.hessian);
      EXPECT_GE(eig.eigenvalues().minCoeff(), -1e-9 * psd.hessian.norm());
      const Vec3 n = obstacle_gap(placed, p).normal;
      EXPECT_NEAR(n.dot(psd.hessian * n), n.dot(exact.hessian * n), 1e-9 * psd.hessian.norm());
    }
  }
}

// The barrier's normal damping at points 0.1-0.9 dhat outside a moving sphere, a
// cylinder's side and a tilted plane: its velocity Jacobian matches central differences of
// its force, the force is minus the gradient of its potential (the line search's term), its
// coefficient is zeta times the critical damping 2 sqrt(m b''), and its dissipation is
// never negative, for velocities toward, away from and along the surface.
TEST(Barrier, NormalDampingMatchesFiniteDifferencesAndNeverAddsEnergy) {
  const double thickness = 0.002, kappa = 5.0, mass = 0.003, zeta = 0.7;  // m, kg/s^2, kg
  const Vec3 c(0.1, -0.2, 0.3), axis = Vec3(0.2, 0.1, 1.0).normalized();
  const Vec3 across = axis.cross(Vec3::UnitX()).normalized();
  const Obstacle obstacles[] = {
      make_obstacle(ObstacleKind::Sphere, c, axis, 0.1, 0, thickness),
      make_obstacle(ObstacleKind::Cylinder, c, axis, 0.1, 0, thickness),
      make_obstacle(ObstacleKind::Plane, c, axis, 0, 0, thickness),
  };
  const Vec3 directions[] = {Vec3(0.3, -0.5, 0.8), Vec3(across + 0.3 * axis), axis};
  const double step = 1e-3;  // m/s
  for (int k = 0; k < 3; ++k) {
    Obstacle ob = obstacles[k];
    ob.motion.velocity = Vec3(0.1, 0.0, -0.2);
    const PlacedObstacle placed = place_obstacle(ob, 0.5);
    for (double fraction : {0.1, 0.5, 0.9}) {
      SCOPED_TRACE(::testing::Message() << obstacle_kind_name(ob.kind) << " at " << fraction
                                        << " dhat");
      Vec3 p = placed.center;
      for (int i = 0; i < 60; ++i) {
        p += (obstacle_gap(placed, p).d - fraction * kDhat) * -directions[k].normalized();
      }
      const Gap g = obstacle_gap(placed, p);
      ASSERT_NEAR(g.d, fraction * kDhat, 1e-12);
      const NormalDamping damping = vertex_damping(placed, p, kappa, mass, kDhat, zeta);
      const double critical =
          2.0 * std::sqrt(mass * barrier_second_derivative(g.d, kDhat, kappa));  // kg/s
      EXPECT_NEAR(damping.coefficient, zeta * critical, 1e-12 * critical);
      const Mat3 jacobian = damping.velocity_jacobian();
      EXPECT_LT((jacobian - jacobian.transpose()).norm(), 1e-12 * jacobian.norm());
      for (const Vec3& v : {Vec3(g.surface_velocity - 0.3 * g.normal),
                            Vec3(g.surface_velocity + 0.2 * g.normal + Vec3(0.1, 0.2, 0.0)),
                            Vec3(g.surface_velocity + g.normal.cross(Vec3::UnitX()))}) {
        Mat3 fd;
        Vec3 gradient;
        for (int j = 0; j < 3; ++j) {
          const Vec3 e = step * Vec3::Unit(j);
          fd.col(j) = (damping.force(v + e) - damping.force(v - e)) / (2 * step);
          gradient[j] = (damping.potential(v + e) - damping.potential(v - e)) / (2 * step);
        }
        EXPECT_LT((fd - jacobian).norm(), 1e-9 * jacobian.norm());
        EXPECT_LT((gradient + damping.force(v)).norm(), 1e-9 * critical);
        EXPECT_GE(damping.dissipation(v), 0.0);
        const double approach = (v - g.surface_velocity).dot(g.normal);  // m/s
        EXPECT_NEAR(damping.dissipation(v), damping.coefficient * approach * approach,
                    1e-12 * critical);
      }
    }
    // No damping beyond dhat, and none without the barrier's band.
    const Vec3 far = placed.center + 10.0 * directions[k].normalized();
    EXPECT_EQ(vertex_damping(placed, far, kappa, mass, kDhat, zeta).coefficient, 0.0);
  }
  // It vanishes continuously at the band's edge, with b'' (as the square root of the
  // distance to it).
  const auto coefficient = [&](double d) {
    return 2.0 * std::sqrt(mass * barrier_second_derivative(d, kDhat, kappa));
  };
  EXPECT_LT(coefficient(kDhat * (1 - 1e-10)), 1e-4 * coefficient(0.5 * kDhat));
}

// The line search's first touch: the gap vanishes there (plane and sphere in closed form;
// the cylinder conservatively, at or just before it), a path that misses gives 1.
TEST(Barrier, FirstTouchIsWhereTheGapVanishes) {
  const double thickness = 0.003;
  const Vec3 c = Vec3::Zero(), axis = Vec3::UnitZ();
  const Obstacle obstacles[] = {
      make_obstacle(ObstacleKind::Plane, c, axis, 0, 0, thickness),
      make_obstacle(ObstacleKind::Sphere, c, axis, 0.2, 0, thickness),
      make_obstacle(ObstacleKind::Cylinder, c, axis, 0.2, 0, thickness),
  };
  for (const Obstacle& ob : obstacles) {
    SCOPED_TRACE(obstacle_kind_name(ob.kind));
    const PlacedObstacle placed = place_obstacle(ob, 0.0);
    const Vec3 p(0.05, 0.02, 0.5), u(0.1, -0.05, -0.6);  // m, m per unit step
    const double t = first_touch(placed, p, u);
    ASSERT_GT(t, 0.0);
    ASSERT_LT(t, 1.0);
    const double d = obstacle_gap(placed, p + t * u).d;
    EXPECT_GE(d, -1e-15);
    EXPECT_LT(d, ob.kind == ObstacleKind::Cylinder ? 1e-3 * 0.5 : 1e-12);
    for (double s : {0.25, 0.5, 0.75, 0.99}) EXPECT_GT(obstacle_gap(placed, p + s * t * u).d, 0.0);
    EXPECT_EQ(first_touch(placed, p, Vec3(0.1, 0.0, 0.1)), 1.0) << "moving away";
    EXPECT_EQ(first_touch(placed, p, 0.1 * u), 1.0) << "too short to reach";
  }
}

// --- Sheets on planes -------------------------------------------------------------------

Sheet barrier_sheet(double size, int nx, double dt) {
  Sheet s = cotton_sheet(size, nx, Integrator::BackwardEuler, dt);
  s.model.implicit.contact = ContactModel::Barrier;
  return s;
}

// The gaps of every vertex to obstacle o at the state's time, m.
std::pair<double, double> gap_range(const Sheet& s, int o) {
  const PlacedObstacle placed = place_obstacle(s.model.obstacles[o], s.state.t);
  double lo = INFINITY, hi = -INFINITY;
  for (const Vec3& p : s.state.x) {
    const double d = obstacle_gap(placed, p).d;
    lo = std::min(lo, d);
    hi = std::max(hi, d);
  }
  return {lo, hi};
}

constexpr double kPlaneThickness = 0.002;  // m

// A sheet of the given size (m) and cells laid half dhat above a plane at z = 0 with
// kPlaneThickness and the given friction coefficient, for steps of dt (s).
Sheet sheet_laid_on_a_plane(double size, int nx, double dt, double friction) {
  Sheet s = barrier_sheet(size, nx, dt);
  s.model.obstacles.push_back(make_obstacle(ObstacleKind::Plane, Vec3::Zero(), Vec3::UnitZ(),
                                            0, friction, kPlaneThickness));
  const double dhat = barrier_distance(s.model);
  for (Vec3& p : s.state.x) p.z() = kPlaneThickness + 0.5 * dhat;
  return s;
}

// The sheet of the sphere tests, 0.6 m in 14 x 14 cells, 5 cm above a sphere of radius
// 0.15 m (thickness 2 mm, friction 0.3) placed slightly off its centre, for steps of dt (s).
Sheet sheet_above_a_sphere(double dt) {
  Sheet s = barrier_sheet(0.6, 14, dt);
  const double radius = 0.15, thickness = 0.002;  // m
  s.model.obstacles.push_back(make_obstacle(ObstacleKind::Sphere, Vec3(0.02, -0.01, -radius - 0.05),
                                            Vec3::UnitZ(), radius, 0.3, thickness));
  return s;
}

// A sheet laid on a plane with friction at half dhat, at 1/30 s: it settles within a second
// steps onto the gap where the barrier holds its weight, inside dhat, and then stays there
// (no creep along the plane, no bounce off it).
TEST(Barrier, SheetRestingOnAPlaneNeitherCreepsNorBounces) {
  Sheet s = sheet_laid_on_a_plane(0.4, 8, 1.0 / 30.0, 0.5);
  const double dhat = barrier_distance(s.model);
  Workspace ws;
  for (int k = 0; k < 30; ++k) ASSERT_FALSE(step(s.model, s.state, ws)) << "settling step " << k;
  const Vec3List settled = s.state.x;
  double drift = 0.0, slide = 0.0, speed = 0.0;
  for (int k = 0; k < 60; ++k) {
    ASSERT_FALSE(step(s.model, s.state, ws)) << "step " << k;
    for (size_t i = 0; i < settled.size(); ++i) {
      const Vec3 moved = s.state.x[i] - settled[i];
      drift = std::max(drift, moved.norm());
      slide = std::max(slide, moved.head<2>().norm());
      speed = std::max(speed, s.state.v[i].norm());
    }
    const auto [lo, hi] = gap_range(s, 0);
    ASSERT_GT(lo, 0.0) << "step " << k;
    ASSERT_LT(hi, dhat) << "step " << k;
  }
  EXPECT_LT(drift, 1e-10);
  EXPECT_LT(slide, 1e-12);
  EXPECT_LT(speed, 1e-9);
}

// A sheet laid on a plane settles, with each implicit method, on the gap where the barrier
// holds its weight: |b'(d)| = m g per vertex. The midpoint rule's barrier acts on the
// end of the step like its other forces, so it pushes no harder than with the other
// methods (it once pushed twice as hard, and settled where |b'| = m g / 2).
TEST(Barrier, EveryMethodRestsWhereTheBarrierHoldsTheWeight) {
  for (Integrator integrator :
       {Integrator::BackwardEuler, Integrator::Bdf2, Integrator::ImplicitMidpoint}) {
    SCOPED_TRACE(integrator_name(integrator));
    Sheet s = sheet_laid_on_a_plane(0.3, 6, 1.0 / 60.0, 0.0);
    s.model.integrator = integrator;
    s.model.air_damping = 1.0;
    const double dhat = barrier_distance(s.model);
    Workspace ws;
    for (int k = 0; k < 240; ++k) ASSERT_FALSE(step(s.model, s.state, ws)) << "step " << k;
    for (int i = 0; i < s.model.num_vertices(); ++i) {
      const double d = s.state.x[i].z() - kPlaneThickness;
      const double kappa = barrier_stiffness(s.model.mass[i], s.model.dt);
      const double weight = s.model.mass[i] * s.model.gravity->norm();  // N
      EXPECT_NEAR(-barrier_derivative(d, dhat, kappa), weight, 1e-3 * weight) << "vertex " << i;
    }
  }
}

// A sheet the scene lays on the plane's thickness, closer than the gap where the barrier
// holds its weight, starts at that gap (lift_to_holding_gaps) and stays at rest there with
// every implicit method and step. Without the start's lift the first step moved it out to
// that gap and kept the motion as velocity: a 0.4 m cotton sheet left the floor at
// 0.06-0.09 m/s at 1/30-1/100 s (docs/implicit.md). Resting, each later step takes one or
// two Newton iterations (4-6 when a line search cut short by rounding kept Newton going).
TEST(Barrier, SheetLaidOnTheThicknessStartsAtRest) {
  for (Integrator integrator :
       {Integrator::BackwardEuler, Integrator::Bdf2, Integrator::ImplicitMidpoint}) {
    for (double dt : {1.0 / 30.0, 1.0 / 60.0, 1.0 / 100.0}) {
      SCOPED_TRACE(std::string(integrator_name(integrator)) + ", dt " + std::to_string(dt));
      Sheet s = sheet_laid_on_a_plane(0.4, 8, dt, 0.5);
      s.model.integrator = integrator;
      for (Vec3& p : s.state.x) p.z() = kPlaneThickness;
      const double dhat = barrier_distance(s.model);
      Workspace ws;
      double fastest = 0.0;  // m/s
      for (int k = 0; k < static_cast<int>(std::lround(0.5 / dt)); ++k) {
        ASSERT_FALSE(step(s.model, s.state, ws)) << "step " << k;
        for (const Vec3& v : s.state.v) fastest = std::max(fastest, v.norm());
        // At rest a step has nothing to solve: one Newton iteration, whose line search
        // sees only rounding in the merit, or two where the first direction's merit never
        // fell (a direction not taken does not settle Newton; the next is taken whole).
        if (k > 0) {
          EXPECT_LE(ws.newton_iterations, 2) << "step " << k;
          continue;
        }
        // After the first step each vertex rests where the barrier holds its weight.
        for (int i = 0; i < s.model.num_vertices(); ++i) {
          const double d = s.state.x[i].z() - kPlaneThickness;
          const double kappa = barrier_stiffness(s.model.mass[i], dt);
          const double weight = s.model.mass[i] * s.model.gravity->norm();  // N
          EXPECT_NEAR(-barrier_derivative(d, dhat, kappa), weight, 1e-3 * weight) << i;
        }
      }
      EXPECT_LT(fastest, 1e-6);
    }
  }
}

// A run's first sample sees the start as the first step takes it: the Stepper places it
// (prepare_start) before any step, and the first step moves it no further. Placed inside
// the first step instead, frame 0 showed the sheet on the thickness and frame 1 showed
// it lifted, a rise of m g dz in the run's energy that no force made.
TEST(Barrier, StepperPlacesTheStartBeforeTheFirstSample) {
  Sheet s = sheet_laid_on_a_plane(0.4, 8, 1.0 / 60.0, 0.5);
  for (Vec3& p : s.state.x) p.z() = kPlaneThickness;
  Stepper stepper(s.model, s.state);
  const double dhat = barrier_distance(s.model);
  for (const Vec3& p : s.state.x) EXPECT_GT(p.z() - kPlaneThickness, 0.1 * dhat);
  const Vec3List placed = s.state.x;
  ASSERT_FALSE(stepper.advance(false));
  for (size_t i = 0; i < placed.size(); ++i) EXPECT_NEAR(s.state.x[i].z(), placed[i].z(), 1e-12) << i;
}

// The gap d (m) at which the barrier of kappa = m / h^2 holds a vertex's weight m g:
// |b'(d)| = m g, i.e. |b'(d)| = g h^2 for kappa = 1 (holding_gap, tested above).
double resting_gap(double dhat, double h, double g) { return holding_gap(g * h * h, dhat, 1.0); }

// A flat sheet dropped 3 cm onto a plane, with the barrier's normal damping at critical
// (zeta = 1, the default), lands and stays, with every implicit method and step. A vertex has landed once its gap has come down to the gap where the barrier holds
// its weight; after that it never rises more than 0.01 dhat (0.1 mm here) above that gap,
// never moves up at more than 5 mm/s while above it, and comes back up to it from the
// compression of its landing at less than 0.1 m/s. Without the barrier's normal damping
// the elastic barrier threw the sheet back up to 0.5-2 dhat at up to 0.44 m/s
// (docs/implicit.md); with it the rise is 0.004 dhat at most, the upward speed 2 mm/s.
// 0.01 dhat is well below the sag between vertices of 2 cm cells; 0.1 m/s is the fastest
// return of a critically damped spring hit at the landing speed V = sqrt(2 g 0.03) =
// 0.77 m/s, V e^-2 (measured: 0.06 m/s at most).
TEST(Barrier, SheetDroppedOnAPlaneLandsWithoutBouncing) {
  const double drop = 0.03;  // m
  for (Integrator integrator :
       {Integrator::BackwardEuler, Integrator::Bdf2, Integrator::ImplicitMidpoint}) {
    for (double h : {1.0 / 240.0, 1.0 / 60.0, 1.0 / 30.0}) {
      SCOPED_TRACE(::testing::Message() << integrator_name(integrator) << " h = " << h);
      Sheet s = barrier_sheet(0.3, 8, h);
      s.model.integrator = integrator;
      s.model.implicit.barrier_damping = 1.0;
      s.model.obstacles.push_back(make_obstacle(ObstacleKind::Plane, Vec3::Zero(),
                                                Vec3::UnitZ(), 0, 0.5, kPlaneThickness));
      for (Vec3& p : s.state.x) p.z() = kPlaneThickness + drop;
      const double dhat = barrier_distance(s.model);
      const double rest = resting_gap(dhat, h, s.model.gravity->norm());  // m
      Workspace ws;
      // A vertex has landed once its gap has come down to the resting gap.
      std::vector<bool> landed(s.state.x.size(), false);
      double rise = 0.0, upward = 0.0, returning = 0.0;  // m above the resting gap, m/s
      const PlacedObstacle placed = place_obstacle(s.model.obstacles[0], 0.0);
      for (int k = 0; k < static_cast<int>(0.5 / h); ++k) {
        ASSERT_FALSE(step(s.model, s.state, ws)) << "step " << k;
        for (size_t i = 0; i < landed.size(); ++i) {
          const double d = obstacle_gap(placed, s.state.x[i]).d;
          ASSERT_GT(d, 0.0) << "step " << k;
          if (!landed[i]) {
            landed[i] = d <= rest;
            continue;
          }
          rise = std::max(rise, d - rest);
          double& speed = d > rest ? upward : returning;  // m/s
          speed = std::max(speed, s.state.v[i].z());
        }
      }
      std::printf("  %s h %.5f s: rise %.3g dhat above the resting gap %.3f dhat, upward %.3g "
                  "m/s above it, %.3g m/s below\n",
                  integrator_name(integrator), h, rise / dhat, rest / dhat, upward, returning);
      ASSERT_TRUE(std::all_of(landed.begin(), landed.end(), [](bool b) { return b; }));
      EXPECT_LT(rise, 0.01 * dhat);
      EXPECT_LT(upward, 0.005);
      EXPECT_LT(returning, 0.1);
    }
  }
}

// A sheet resting closer to a plane than dhat / 2 (a softer barrier, kappa from a step of
// 0.1 s, holds its weight at about 0.17 dhat) starts each step where it rests: the step
// equation's residual at the initial guess is at rounding level. The guess once lifted
// every such vertex to dhat / 2, so that each resting step began stretched (a residual of
// twice gravity's impulse) and took 4 Newton iterations to pull back.
TEST(Barrier, RestingStepStartsWhereTheSheetRests) {
  Sheet s = sheet_laid_on_a_plane(0.3, 6, 1.0 / 60.0, 0.5);
  s.model.implicit.barrier_stiffness_dt = 0.1;  // s
  const double dhat = barrier_distance(s.model);
  double mass = 0.0;  // kg
  for (double m : s.model.mass) mass += m;
  // Gravity's impulse over the step in the residual's norm, sqrt(kg) m/s.
  const double gravity = s.model.dt * s.model.gravity->norm() * std::sqrt(mass);
  Workspace ws;
  for (int k = 0; k < 60; ++k) ASSERT_FALSE(step(s.model, s.state, ws)) << "settling step " << k;
  ASSERT_LT(gap_range(s, 0).second, 0.25 * dhat) << "the sheet rests closer than dhat / 2";
  for (int k = 0; k < 30; ++k) {
    ASSERT_FALSE(step(s.model, s.state, ws)) << "step " << k;
    EXPECT_LT(last_implicit_report(ws)->initial_residual, 1e-6 * gravity) << "step " << k;
  }
}

// --- A sphere ---------------------------------------------------------------------------

// A sheet dropped onto a sphere with large steps, with each implicit method: no vertex ever
// ends a step at or inside the sphere's thickness, and contact does no work: the total
// energy, the barrier's included, never rises above its value at the start. (The midpoint
// rule gained 0.21 J at 1/60 s here before its steps with the barrier were checked for
// energy and halved; docs/implicit.md, "A barrier instead of constraints".)
TEST(Barrier, SheetDroppedOnASphereNeverEndsInsideNorGainsEnergy) {
  for (Integrator integrator :
       {Integrator::BackwardEuler, Integrator::Bdf2, Integrator::ImplicitMidpoint}) {
    for (double h : {1.0 / 60.0, 1.0 / 30.0}) {
      SCOPED_TRACE(::testing::Message() << integrator_name(integrator) << " h = " << h);
      Sheet s = sheet_above_a_sphere(h);
      s.model.integrator = integrator;
      s.model.air_damping = 0.3;
      Workspace ws;
      const double e0 = total_energy(s.model, s.state);
      double closest = INFINITY, highest = -INFINITY;
      for (int k = 0; k < static_cast<int>(1.5 / h); ++k) {
        ASSERT_FALSE(step(s.model, s.state, ws)) << "step " << k;
        closest = std::min(closest, gap_range(s, 0).first);
        highest = std::max(highest, total_energy(s.model, s.state) +
                                      barrier_energy_of(s.model, s.state.x, s.state.t) - e0);
      }
      std::printf("  %s h %.4f s: largest energy rise %.3g J, closest gap %.3g m\n",
                  integrator_name(integrator), h, highest, closest);
      EXPECT_GT(closest, 0.0);
      EXPECT_LT(closest, barrier_distance(s.model)) << "the sheet lands on the sphere";
      EXPECT_LE(highest, 1e-9);
    }
  }
}

// The report's per-iteration record of the line search (what tissu_implicit_profile
// --detail prints): one entry per Newton iteration in each list; the length taken is at
// most the barrier's longest step, the merit never rises, and the vertices within dhat are
// counted. Landing on the sphere at 1/30 s, some first direction would carry a vertex
// into the sphere, and the longest step is shorter than 1 there.
TEST(Barrier, ReportRecordsEachIterationsLineSearch) {
  const double h = 1.0 / 30.0;  // s
  Sheet s = sheet_above_a_sphere(h);
  Workspace ws;
  int capped = 0, near = 0;  // iterations cut short by the barrier; largest count within dhat
  for (int k = 0; k < static_cast<int>(0.5 / h); ++k) {
    ASSERT_FALSE(step(s.model, s.state, ws)) << "step " << k;
    const ImplicitReport& r = *last_implicit_report(ws);
    const size_t n = static_cast<size_t>(r.newton_iterations);
    ASSERT_EQ(r.step_lengths.size(), n) << "step " << k;
    ASSERT_EQ(r.feasible_lengths.size(), n) << "step " << k;
    ASSERT_EQ(r.merit_changes.size(), n) << "step " << k;
    ASSERT_EQ(r.barrier_contacts.size(), n) << "step " << k;
    for (size_t i = 0; i < n; ++i) {
      EXPECT_LE(r.step_lengths[i], r.feasible_lengths[i]) << "step " << k << " iteration " << i;
      EXPECT_LE(r.merit_changes[i], 0.0) << "step " << k << " iteration " << i;
      capped += r.feasible_lengths[i] < 1.0 ? 1 : 0;
      near = std::max(near, r.barrier_contacts[i]);
    }
  }
  EXPECT_GT(capped, 0) << "no direction was cut short at the sphere";
  EXPECT_GT(near, 0) << "the sheet lands within dhat";
}

// The same sheet thrown at 2 m/s onto the sphere, with BDF-2 at 1/60 s, a 1 mm barrier and
// its normal damping at critical: it neither diverges nor gains energy, and no vertex ends
// inside. Near the surface the damping's coefficient grows like 1/d, as the barrier's
// force does; uncapped, it held vertices leaving the surface against it, pressed them
// ever closer, and the run gained 1.3 J in its second step and diverged in its third (the
// demo's divergence at t = 0.48 s, in a second's worth of small steps; kMaxStepDamping).
TEST(Barrier, SheetThrownOnASphereWithDampingNeitherDivergesNorGainsEnergy) {
  const double h = 1.0 / 60.0;  // s
  Sheet s = sheet_above_a_sphere(h);
  s.model.integrator = Integrator::Bdf2;
  s.model.implicit.barrier_damping = 1.0;
  s.model.implicit.barrier_distance = 0.001;  // m
  s.model.air_damping = 0.3;
  for (Vec3& v : s.state.v) v = Vec3(0.0, 0.0, -2.0);  // m/s
  Workspace ws;
  const double e0 = total_energy(s.model, s.state);
  double highest = -INFINITY, closest = INFINITY;
  for (int k = 0; k < static_cast<int>(1.0 / h); ++k) {
    ASSERT_FALSE(step(s.model, s.state, ws)) << "step " << k;
    closest = std::min(closest, gap_range(s, 0).first);
    highest = std::max(highest, total_energy(s.model, s.state) +
                                  barrier_energy_of(s.model, s.state.x, s.state.t) - e0);
  }
  std::printf("  largest energy rise %.3g J, closest gap %.3g m\n", highest, closest);
  EXPECT_GT(closest, 0.0);
  EXPECT_LT(closest, 0.001) << "the sheet lands on the sphere";
  EXPECT_LE(highest, 1e-9);
}

// A midpoint step with the barrier that gains energy is taken again as two halves
// (implicit.cpp, energy_ruled_step); the step's Newton, CG and factorization counts
// then include every solve it made, not only the last half's. On the sheet dropped on the
// sphere at 1/60 s some steps are halved: those solved in one substep report more Newton
// iterations than their last solve made. A step never reports fewer.
TEST(Barrier, HalvedMidpointStepCountsEverySolve) {
  const double h = 1.0 / 60.0;  // s
  Sheet s = sheet_above_a_sphere(h);
  s.model.integrator = Integrator::ImplicitMidpoint;
  s.model.air_damping = 0.3;
  Workspace ws;
  int halved = 0;  // one-substep steps that counted more than their last solve
  for (int k = 0; k < static_cast<int>(0.5 / h); ++k) {
    ASSERT_FALSE(step(s.model, s.state, ws)) << "step " << k;
    const ImplicitReport& last = *last_implicit_report(ws);
    EXPECT_GE(ws.newton_iterations, last.newton_iterations) << "step " << k;
    EXPECT_GE(ws.cg_iterations, last.cg_iterations) << "step " << k;
    EXPECT_GE(ws.factorizations, last.factorizations) << "step " << k;
    if (ws.substeps == 1 && ws.newton_iterations > last.newton_iterations) ++halved;
  }
  EXPECT_GT(halved, 0) << "no halved step counted its discarded and first solves";
}

}  // namespace
}  // namespace tissu
