// Finite-difference checks of a barrier step's impulses and matrix against its potential
// (barrier_contact.h), shared by the barrier tests.
#pragma once

#include <gtest/gtest.h>

#include <Eigen/Core>

#include "physics/barrier_contact.h"

namespace tissu::testing {

// -impulse = d potential / dv (central differences of 1e-7 m/s) at v.
inline void expect_impulses_match_potential(const BarrierContact& contact, const Vec3List& v) {
  const int n = static_cast<int>(v.size());
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(3 * n);
  contact.add_impulses(v, rhs);
  const double step = 1e-7;  // m/s
  for (int k = 0; k < 3 * n; ++k) {
    Vec3List plus = v, minus = v;
    plus[k / 3][k % 3] += step;
    minus[k / 3][k % 3] -= step;
    const double slope = (contact.potential(plus) - contact.potential(minus)) / (2 * step);
    EXPECT_NEAR(-rhs[k], slope, 1e-5 * rhs.norm()) << k;
  }
}

// The potential's second derivative at v along `direction` (3V, m/s per unit), by central
// differences of e.
inline double potential_curvature(const BarrierContact& contact, const Vec3List& v,
                                  const Eigen::VectorXd& direction, double e) {
  Vec3List ahead = v, behind = v;
  for (size_t i = 0; i < v.size(); ++i) {
    ahead[i] += e * Vec3(direction.segment<3>(3 * i));
    behind[i] -= e * Vec3(direction.segment<3>(3 * i));
  }
  return (contact.potential(ahead) - 2 * contact.potential(v) + contact.potential(behind)) /
         (e * e);
}

}  // namespace tissu::testing
