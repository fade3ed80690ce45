// Friction on a mesh obstacle's edge against Coulomb's capstan law: a cotton strip lying
// on the top of a box given as a triangle mesh, a length a on the top, over one of its edges
// and b hanging down the side. On the top the tension grows from nothing at the free end to
// mu rho g a at the edge; over the edge (a quarter turn) it grows by exp(mu pi / 2) (the
// capstan law does not depend on the radius, so a sharp edge takes the same share as a
// round one), and the side, vertical, presses nothing. The strip holds while
//   b <= mu a exp(mu pi / 2),
// and without friction on the edge only while b <= mu a.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "physics/step.h"
#include "strip_checks.h"
#include "test_meshes.h"

namespace tissu {
namespace {

constexpr double kFriction = 0.3;    // Coulomb coefficient
constexpr double kTop = 0.3;         // m of strip on the top
constexpr double kWidth = 0.1;       // m
constexpr double kThickness = 0.002;  // m, the box's
// m between the laid strip and the box's layer: enough that the cloth edges cutting the
// corner (cells of 1 cm over a turn of a few millimetres) lie beyond the layer too.
constexpr double kClearance = 3e-3;

double capstan_limit() { return kFriction * kTop * std::exp(kFriction * M_PI / 2); }

// The strip laid over the box's edge along y at x = z = 0 (top z = 0, side x = 0), cells
// of 1 cm: on the top from x = -kTop, round the edge on a quarter circle, down the side.
testing::Sheet strip_over_edge(double hanging, Integrator integrator, double dt,
                               ContactModel contact) {
  const double r = kThickness + kClearance, turn = M_PI / 2 * r;
  const double length = kTop + turn + hanging;
  const int cells = static_cast<int>(std::round(length / 0.01));
  testing::Sheet s = testing::cotton_rectangle(length, kWidth, cells, 5, integrator, dt);
  for (size_t i = 0; i < s.state.x.size(); ++i) {
    const double arc = s.model.rest_uv[i].x() + length / 2, y = s.model.rest_uv[i].y();
    if (arc <= kTop) {
      s.state.x[i] = Vec3(arc - kTop, y, r);
    } else if (arc <= kTop + turn) {
      const double th = (arc - kTop) / r;
      s.state.x[i] = Vec3(r * std::sin(th), y, r * std::cos(th));
    } else {
      s.state.x[i] = Vec3(r, y, -(arc - kTop - turn));
    }
  }
  s.model.implicit.contact = contact;
  s.model.obstacles.push_back(
      testing::mesh_box(Vec3(-0.4, -0.2, -0.4), Vec3(0.0, 0.2, 0.0), kThickness, kFriction));
  return s;
}

// How far (m) the strip's hanging end goes down in `seconds`.
double hanging_end_drop(double hanging, Integrator integrator, double dt, ContactModel contact,
                        double seconds) {
  testing::Sheet s = strip_over_edge(hanging, integrator, dt, contact);
  return testing::lowest_vertex_drop(s, seconds);
}

struct Case {
  Integrator integrator;
  double dt;  // s
  ContactModel contact;
};

void expect_capstan_limit(const Case& c) {
  SCOPED_TRACE(std::string(integrator_name(c.integrator)) + " at " + std::to_string(c.dt) +
               " s, " + (c.contact == ContactModel::Barrier ? "barrier" : "constraints"));
  const double limit = capstan_limit();  // 0.144 m: 0.48 times kTop
  // Held: the strip settles onto the box (the clearance, 3 mm) and stays.
  EXPECT_LT(hanging_end_drop(0.8 * limit, c.integrator, c.dt, c.contact, 0.6), 0.005);
  // Not held: the excess weight pulls the strip off the top.
  EXPECT_GT(hanging_end_drop(1.25 * limit, c.integrator, c.dt, c.contact, 0.6), 0.04);
}

// The barrier holds the strip off the box's edge with its edge pairs (mesh_barrier.h),
// which carry the turn's normal force: without friction on them the strip slid off at 0.8
// times the limit (0.20 m with backward Euler at 1/240 s, 0.066 m with BDF-2 at 1/60 s),
// as it would at 0.62 times (b = mu a).
TEST(EdgeFriction, BarrierHoldsBelowTheLimitAndSlidesAbove) {
  expect_capstan_limit({Integrator::BackwardEuler, 1.0 / 240.0, ContactModel::Barrier});
  expect_capstan_limit({Integrator::BackwardEuler, 1.0 / 60.0, ContactModel::Barrier});
  expect_capstan_limit({Integrator::Bdf2, 1.0 / 60.0, ContactModel::Barrier});
}

// Under the constraints the vertices' contacts carry the turn, with their own friction.
TEST(EdgeFriction, ConstraintsHoldBelowTheLimitAndSlideAbove) {
  expect_capstan_limit({Integrator::BackwardEuler, 1.0 / 240.0, ContactModel::Constraints});
  expect_capstan_limit({Integrator::Bdf2, 1.0 / 240.0, ContactModel::Constraints});
}

// Known faults (docs/implicit.md): symplectic Euler slides at 0.7 times the limit (0.098 m
// in 0.6 s; it holds at 0.5), as if the edge had no friction; BDF-2 with the barrier at
// 1/240 s creeps at 0.8 times (0.045 m in 0.6 s, steadily).
TEST(EdgeFriction, DISABLED_SymplecticEulerHoldsBelowTheLimitAndSlidesAbove) {
  expect_capstan_limit({Integrator::SymplecticEuler, 2.5e-5, ContactModel::Constraints});
}

TEST(EdgeFriction, DISABLED_Bdf2WithTheBarrierAtSmallStepsHoldsBelowTheLimit) {
  expect_capstan_limit({Integrator::Bdf2, 1.0 / 240.0, ContactModel::Barrier});
}

}  // namespace
}  // namespace tissu
