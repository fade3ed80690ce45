// Biphasic membrane response (Material::compression_ratio): the yarns of a woven fabric
// buckle under axial compression (Choi & Ko 2002's post-buckling response, for springs),
// so the membrane resists compression along the weft or warp far less than stretching.
//
// Each of the two yarn strains (e_uu, e_vv) enters the energy through phi:
//   phi(e) = e                                            e >= 0
//   phi(e) = k e + (1 - k) d (exp(e / d) - 1),  k = sqrt(kappa)   e < 0
// and W = A/2 e~^T E e~ with e~ = (phi(e_uu), phi(e_vv), e_uv). phi' goes smoothly from 1 at
// e = 0 to k beyond a few d of compression, so the compressive stiffness tends to kappa
// times the tensile one (the coupling to sqrt(kappa) times) and W stays >= 0. phi is C1
// (phi'' jumps at 0 only): forces are continuous where a strain changes sign, as Newton
// needs; with phi' jumping instead, the weft-warp coupling made the forces jump by tens of
// a vertex's weight in the drape test (docs/bending.md).
//
// Derivatives, for the forces and the Jacobian (D = diag(phi'_uu, phi'_vv, 1)):
//   stress dW/de / A            = D E e~
//   material tangent d2W/de2 / A = D E D + diag(phi''_uu (E e~)_uu, phi''_vv (E e~)_vv, 0)
#pragma once

#include <cmath>

#include "core/types.h"

namespace tissu {

// d: the compressive strain over which the slope phi' falls (by 1/e of its drop). Small
// next to the drape's compressive strains (up to about 1e-2 at kappa 0.01) and large next
// to Newton's round-off.
constexpr double kYarnBucklingStrain = 1e-3;

struct BiphasicStrain {
  Vec3 mapped;     // e~ = (phi(e_uu), phi(e_vv), e_uv)
  Vec3 slope;      // (phi'(e_uu), phi'(e_vv), 1)
  Vec3 curvature;  // (phi''(e_uu), phi''(e_vv), 0)
};

// The mapped strain of Green strain e under the compression ratio kappa in (0, 1].
inline BiphasicStrain biphasic_strain(const Vec3& e, double kappa) {
  BiphasicStrain b{e, Vec3::Ones(), Vec3::Zero()};
  const double k = std::sqrt(kappa), d = kYarnBucklingStrain;
  for (int a = 0; a < 2; ++a) {
    if (e[a] >= 0.0 || kappa >= 1.0) continue;
    const double decay = std::exp(e[a] / d);
    b.mapped[a] = k * e[a] + (1.0 - k) * d * (decay - 1.0);
    b.slope[a] = k + (1.0 - k) * decay;
    b.curvature[a] = (1.0 - k) * decay / d;
  }
  return b;
}

}  // namespace tissu
