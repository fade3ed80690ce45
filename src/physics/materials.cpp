// Fabric presets. Sources, in short (full citations, unit checks and the reasoning behind
// every estimate are in docs/materials.md):
//   [Clyde17]  Clyde, Teran & Tamstorf 2017, "Modeling and data-driven parameter estimation
//              for woven fabrics", as transcribed in Codim-IPC (Apache-2.0),
//              Python/Drivers/FEMDiscreteShellBase.py: areal density, thickness 0.18 mm and
//              the orthotropic StVK coefficients (Pa) of cotton and silk.
//   [Feng22]   Feng et al. 2022, "Learning-based bending stiffness parameter estimation by a
//              drape tester", data set DrapeTester/ClothDrapeTester dataset/dataset.csv
//              (618 fabrics, no fibre labels): bending lengths of fabrics of similar weight.
//   [est]      estimated here; the reasoning is in docs/materials.md.
//
// Conventions: u = weft, v = warp. E = [[weft, coupling, 0], [coupling, warp, 0],
// [0, 0, shear]] acts on Green strain (e_uu, e_vv, e_uv = U.V), so the energy density is
// 1/2 e^T E e. Codim-IPC writes psi = C0/2 E00^2 + C1 E00 E11 + C2/2 E11^2 + C3 E01^2 per
// unit volume, with E01 = e_uv/2; hence weft = C0 h, coupling = C1 h, warp = C2 h and
// shear = C3 h / 2 (C3 E01^2 = 1/2 (C3/2) e_uv^2).
#include "physics/materials.h"

#include <cmath>

namespace tissu {

namespace {

constexpr double kGravity = 9.80665;            // m/s^2, standard gravity
constexpr double kClydeThickness = 0.18e-3;     // m, cotton and silk [Clyde17]
constexpr double kWarpWeftBendingRatio = 1.2;   // B_warp / B_weft, median of 24 [Feng22] rows [est]
constexpr double kDampingTime = 1.0e-5;         // s, numerical strain-rate damping [est]

// Peirce's cantilever relation B = rho_A g c^3, split into weft and warp rigidities whose
// geometric mean is the rigidity of bending length c (see docs/materials.md).
void set_bending(Material& m, double bending_length) {
  const double b = m.density * kGravity * bending_length * bending_length * bending_length;
  m.bending = b / std::sqrt(kWarpWeftBendingRatio);       // weft, N*m
  m.bending_warp = b * std::sqrt(kWarpWeftBendingRatio);  // warp, N*m
}

// A preset from its areal density (kg/m^2), membrane stiffnesses (N/m) and bending length
// (m, set_bending), with the numerical damping.
Material preset(const char* name, double density, double weft, double warp, double coupling,
                double shear, double bending_length) {
  Material m;
  m.name = name;
  m.density = density;
  m.weft = weft;
  m.warp = warp;
  m.coupling = coupling;
  m.shear = shear;
  set_bending(m, bending_length);
  m.damping = kDampingTime;  // s [est]
  return m;
}

// 103.6 g/m^2 [Clyde17] (unit read as g/m^2). Membrane: C11 15.557, C22 25.004, C12 7.779,
// C3 1.076 MPa times the thickness 0.18 mm (shear C3 t / 2) [Clyde17], that is weft 2800.3,
// warp 4500.7, coupling 1400.2, shear 96.84 N/m. c = 1.65 cm: median of [Feng22] rows of
// 0.098-0.109 kg/m^2 [est].
Material cotton() {
  const double t = kClydeThickness;
  return preset("cotton", 0.1036, 15.557e6 * t, 25.004e6 * t, 7.779e6 * t, 1.076e6 * t / 2,
                0.0165);
}

// No measured linen set was found: linen is a heavier cloth of the cotton construction, its
// membrane the cotton one scaled by the areal-density ratio (more yarn per width) [est]:
// weft 5000.5, warp 8037.0, coupling 2500.4, shear 172.93 N/m. Density: middle of the
// 150-220 g/m^2 class linen falls in [est]. c = 2.26 cm: median of [Feng22] rows of
// 0.176-0.194 kg/m^2 [est].
Material linen() {
  constexpr double kScale = 0.185 / 0.1036;  // linen / cotton areal density
  const Material c = cotton();
  return preset("linen", 0.185, c.weft * kScale, c.warp * kScale, c.coupling * kScale,
                c.shear * kScale, 0.0226);
}

// 83 g/m^2 [Clyde17] (unit read as g/m^2). Membrane: C11 4.3, C22 9.942, C12 4.971, C3 0.57
// MPa times the thickness 0.18 mm (shear C3 t / 2) [Clyde17], that is weft 774.0, warp
// 1789.6, coupling 894.8, shear 51.3 N/m. c = 1.2 cm: lightest-drape end of [Feng22] rows
// of its weight [est].
Material silk() {
  const double t = kClydeThickness;
  return preset("silk", 0.083, 4.3e6 * t, 9.942e6 * t, 4.971e6 * t, 0.57e6 * t / 2, 0.012);
}

}  // namespace

std::optional<Material> material_preset(const std::string& name) {
  if (name == "cotton") return cotton();
  if (name == "linen") return linen();
  if (name == "silk") return silk();
  return std::nullopt;
}

std::vector<std::string> material_preset_names() { return {"cotton", "linen", "silk"}; }

}  // namespace tissu
