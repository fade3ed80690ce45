// Friction on a curved obstacle against Coulomb's capstan law: a cotton strip hung over a
// horizontal cylinder, a lengths hanging on one side and b on the other. The strip's own
// weight on the cylinder presses it too, so the tension T (N/m) along the wrap, at angle th
// from the top, obeys (per unit width, rho the strip's areal density, R the radius)
//   dT/dth = mu T + rho g R (mu cos th - sin th)      (sliding toward th = +pi/2)
// from T(-pi/2) = rho g a; the strip holds while rho g b <= T(pi/2) (Coulomb's capstan
// equation with a heavy rope; without its weight b / a = exp(mu pi)). Below that limit
// every integrator must leave the strip where it lies, above it the strip must slide off,
// and (sliding) go down as an inextensible rope does.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "physics/step.h"
#include "strip_checks.h"
#include "test_meshes.h"

namespace tissu {
namespace {

constexpr double kG = 9.81;         // m/s^2
constexpr double kRadius = 0.05;    // m
constexpr double kFriction = 0.3;   // Coulomb coefficient
constexpr double kLeft = 0.2;       // m of strip hanging on the light side
constexpr double kWidth = 0.1;      // m
constexpr double kClearance = 5e-4;  // m between the laid strip and the cylinder

// The tension (N/m, per unit rho) at th = pi/2 of an inextensible rope of hanging length
// `left` (m) on the light side, sliding at u (m/s) toward the heavy side with acceleration
// a (m/s^2): along the wrap
//   dT/dth = mu (T - u^2) + g R (mu cos th - sin th) + R a
// (the normal force T / R + g cos th - u^2 / R, the centrifugal part included), from
// T(-pi/2) = left (g + a); RK4. At rest (u = a = 0) it is the capstan ODE above.
double wrap_tension(double left, double u, double a) {
  auto slope = [&](double th, double t) {
    return kFriction * (t - u * u) + kG * kRadius * (kFriction * std::cos(th) - std::sin(th)) +
           kRadius * a;
  };
  const int n = 200;
  const double d = M_PI / n;
  double th = -M_PI / 2, t = left * (kG + a);
  for (int i = 0; i < n; ++i) {
    const double k1 = slope(th, t), k2 = slope(th + d / 2, t + d / 2 * k1);
    const double k3 = slope(th + d / 2, t + d / 2 * k2), k4 = slope(th + d, t + d * k3);
    t += d / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
    th += d;
  }
  return t;
}

// The largest b (m) that the capstan law holds against kLeft: T(pi/2) = g b at rest.
double capstan_limit() { return wrap_tension(kLeft, 0.0, 0.0) / kG; }

// How far (m) the heavy end of an inextensible rope of hanging lengths kLeft and `right`
// goes down in `seconds`, from rest: each moment's a makes wrap_tension meet the heavy
// side's right (g - a), linear in a, and the hanging lengths change by the distance slid.
// Semi-implicit Euler at 0.1 ms.
double rope_drop(double right, double seconds) {
  const double dt = 1e-4;
  double slid = 0.0, u = 0.0;
  for (int k = 0; k < static_cast<int>(std::round(seconds / dt)); ++k) {
    const double left = kLeft - slid, heavy = right + slid;
    const double r0 = wrap_tension(left, u, 0.0) - heavy * kG;
    const double r1 = wrap_tension(left, u, 1.0) - heavy * (kG - 1.0);
    const double a = std::max(-r0 / (r1 - r0), u > 0.0 ? -INFINITY : 0.0);
    u += a * dt;
    slid += u * dt;
  }
  return slid;
}

// The strip of hanging lengths kLeft and `right` (m), laid kClearance off the cylinder
// (axis y through the origin): cells of about 2 cm, rest (u, v) = (arc length, width).
testing::Sheet strip_over_cylinder(double right, Integrator integrator, double dt) {
  const double r = kRadius + kClearance, wrap = M_PI * r;
  const double length = kLeft + wrap + right;
  const int cells = static_cast<int>(std::round(length / 0.02));
  testing::Sheet s = testing::cotton_rectangle(length, kWidth, cells, 5, integrator, dt);
  for (size_t i = 0; i < s.state.x.size(); ++i) {
    const double arc = s.model.rest_uv[i].x() + length / 2, y = s.model.rest_uv[i].y();
    if (arc <= kLeft) {
      s.state.x[i] = Vec3(-r, y, -(kLeft - arc));
    } else if (arc <= kLeft + wrap) {
      const double th = -M_PI / 2 + (arc - kLeft) / r;
      s.state.x[i] = Vec3(r * std::sin(th), y, r * std::cos(th));
    } else {
      s.state.x[i] = Vec3(r, y, -(arc - kLeft - wrap));
    }
  }
  Obstacle cylinder = testing::make_obstacle(ObstacleKind::Cylinder, Vec3::Zero(), Vec3::UnitY(),
                                             kRadius, kFriction, 0.0);
  cylinder.half_length = kWidth;
  s.model.obstacles.push_back(cylinder);
  return s;
}

// How far (m) the strip's heavy end goes down in `seconds`.
double heavy_end_drop(double right, Integrator integrator, double dt, double seconds) {
  testing::Sheet s = strip_over_cylinder(right, integrator, dt);
  return testing::lowest_vertex_drop(s, seconds);
}

struct Case {
  Integrator integrator;
  double dt;  // s
};

void expect_capstan_limit(const Case& c) {
  SCOPED_TRACE(std::string(integrator_name(c.integrator)) + " at " + std::to_string(c.dt) + " s");
  const double limit = capstan_limit();  // 0.611 m: 3.06 times kLeft
  // Held: the strip settles onto the cylinder (about a millimetre) and stays.
  const double held = heavy_end_drop(0.8 * limit, c.integrator, c.dt, 0.6);
  const double pulled = heavy_end_drop(1.25 * limit, c.integrator, c.dt, 0.6);
  EXPECT_LT(held, 0.005);
  // Not held: the excess weight pulls the strip off, faster and faster (an inextensible
  // rope goes down 0.45 m in 0.6 s at 1.25 times the limit: rope_drop).
  EXPECT_GT(pulled, 0.1);
}

TEST(Capstan, LimitIsTheRopeLawsWithItsOwnWeight) {
  // Without the wrap's weight the ratio would be exp(mu pi) = 2.57; its weight adds normal
  // force (friction) on the top and pull on the heavy side's quarter.
  EXPECT_NEAR(capstan_limit() / kLeft, 3.057, 0.001);
}

TEST(Capstan, SymplecticEulerHoldsBelowTheLimitAndSlidesAbove) {
  expect_capstan_limit({Integrator::SymplecticEuler, 2.5e-5});
}

// Sliding too: symplectic Euler's strip goes down as the rope does, within 5% after 0.6 s
// (the slide roughly doubles every 0.1 s, so any error in the friction or the centrifugal
// relief grows with it). The implicit methods at 1/240 s lag it by 18-26%.
TEST(Capstan, SymplecticEulerSlidesOffAsTheRopeDoes) {
  const double right = 1.25 * capstan_limit(), rope = rope_drop(right, 0.6);  // m
  EXPECT_NEAR(rope, 0.448, 0.005);
  EXPECT_NEAR(heavy_end_drop(right, Integrator::SymplecticEuler, 2.5e-5, 0.6), rope, 0.05 * rope);
}

// The constraints (the default contact model) at 1/240 s. At 1/60 s backward Euler and
// BDF-2 hold this coarse strip (cells of 2 cm on a 5 cm radius) even at 1.25 times the
// limit (its heavy end down 38 and 58 mm in 0.6 s, against 0.37 and 0.33 m at 1/240 s and
// 0.45 m with symplectic Euler): not done, docs/implicit.md ("Friction on a curved
// obstacle").
TEST(Capstan, BackwardEulerHoldsBelowTheLimitAndSlidesAbove) {
  expect_capstan_limit({Integrator::BackwardEuler, 1.0 / 240.0});
}

TEST(Capstan, Bdf2HoldsBelowTheLimitAndSlidesAbove) {
  expect_capstan_limit({Integrator::Bdf2, 1.0 / 240.0});
}

// Not met, and so disabled: the midpoint rule holds the strip at 1.25 times the limit
// (12 mm in 0.6 s at 1/60 and 1/240 s), and lets it settle 6-7 mm at 0.8 times.
TEST(Capstan, DISABLED_ImplicitMidpointHoldsBelowTheLimitAndSlidesAbove) {
  expect_capstan_limit({Integrator::ImplicitMidpoint, 1.0 / 240.0});
}

}  // namespace
}  // namespace tissu
