// Fabric presets (src/physics/materials.h): every preset exists, fills every field with a
// physically sensible value, and its stiffness matrix is positive definite.
#include "physics/materials.h"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <set>
#include <string>

namespace tissu {
namespace {

constexpr double kG = 9.80665;  // m/s^2

Material preset(const std::string& name) {
  const std::optional<Material> m = material_preset(name);
  if (!m) ADD_FAILURE() << "no preset named " << name;
  return m.value_or(Material{});
}

// Peirce's bending length c = (B / (rho_A g))^(1/3), m.
double bending_length(double rigidity, double density) {
  return std::cbrt(rigidity / (density * kG));
}

TEST(MaterialPresets, NamesAreTheThreeFabricsOfThePaperAndAllResolve) {
  const std::vector<std::string> names = material_preset_names();
  EXPECT_EQ(names, (std::vector<std::string>{"cotton", "linen", "silk"}));
  std::set<std::string> unique(names.begin(), names.end());
  EXPECT_EQ(unique.size(), names.size());
  for (const std::string& name : names) {
    const std::optional<Material> m = material_preset(name);
    ASSERT_TRUE(m.has_value()) << name;
    EXPECT_EQ(m->name, name);
  }
}

TEST(MaterialPresets, UnknownNameGivesNullopt) {
  EXPECT_FALSE(material_preset("wool").has_value());
  EXPECT_FALSE(material_preset("").has_value());
  EXPECT_FALSE(material_preset("custom").has_value());
  EXPECT_FALSE(material_preset("cotton ").has_value());
}

TEST(MaterialPresets, EveryFieldIsFilled) {
  for (const std::string& name : material_preset_names()) {
    const Material m = preset(name);
    EXPECT_GT(m.density, 0.0) << name;
    EXPECT_GT(m.weft, 0.0) << name;
    EXPECT_GT(m.warp, 0.0) << name;
    EXPECT_GT(m.coupling, 0.0) << name;  // woven fabrics contract laterally when stretched
    EXPECT_GT(m.shear, 0.0) << name;
    EXPECT_GT(m.bending, 0.0) << name;
    EXPECT_GT(m.bending_warp, 0.0) << name;  // set explicitly, not the "same as weft" default
    EXPECT_GE(m.damping, 0.0) << name;
    EXPECT_LE(m.damping, 1e-3) << name;  // s: small, so it only calms the stiff modes
  }
}

TEST(MaterialPresets, StiffnessMatrixIsPositiveDefinite) {
  for (const std::string& name : material_preset_names()) {
    const Material m = preset(name);
    const Mat3 e = m.stiffness();
    // The matrix the simulator uses is the one the fields describe.
    EXPECT_EQ(e(0, 0), m.weft) << name;
    EXPECT_EQ(e(1, 1), m.warp) << name;
    EXPECT_EQ(e(0, 1), m.coupling) << name;
    EXPECT_EQ(e(1, 0), m.coupling) << name;
    EXPECT_EQ(e(2, 2), m.shear) << name;
    // Sylvester's criterion: leading principal minors all positive.
    EXPECT_GT(e(0, 0), 0.0) << name;
    const double minor2 = e(0, 0) * e(1, 1) - e(0, 1) * e(1, 0);
    EXPECT_GT(minor2, 0.0) << name;
    EXPECT_GT(e.determinant(), 0.0) << name;
    // And the eigenvalues, with a margin: the smallest is not a rounding accident.
    Eigen::SelfAdjointEigenSolver<Mat3> solver(e);
    ASSERT_EQ(solver.info(), Eigen::Success) << name;
    const Eigen::Vector3d eig = solver.eigenvalues();  // ascending
    EXPECT_GT(eig(0), 1e-3 * eig(2)) << name << ": condition number above 1000";
  }
}

TEST(MaterialPresets, MembraneStiffnessesAreThoseOfRealWovenFabrics) {
  for (const std::string& name : material_preset_names()) {
    const Material m = preset(name);
    // Tensile stiffness of woven fabrics: hundreds to thousands of N/m.
    EXPECT_GE(std::min(m.weft, m.warp), 100.0) << name;
    EXPECT_LE(std::max(m.weft, m.warp), 10000.0) << name;
    // Shear is 10 to 100 times softer than tension.
    EXPECT_GE(std::min(m.weft, m.warp) / m.shear, 10.0) << name;
    EXPECT_LE(std::max(m.weft, m.warp) / m.shear, 100.0) << name;
  }
}

TEST(MaterialPresets, DensitiesArePhysicalAndOrdered) {
  for (const std::string& name : material_preset_names()) {
    const double rho = preset(name).density;
    EXPECT_GE(rho, 0.03) << name;
    EXPECT_LE(rho, 0.5) << name;
  }
  // Clyde et al. 2017: silk 83 g/m^2 < cotton 103.6 g/m^2; linen is the heavier cloth.
  EXPECT_LT(preset("silk").density, preset("cotton").density);
  EXPECT_LT(preset("cotton").density, preset("linen").density);
}

TEST(MaterialPresets, BendingLengthsAreThoseOfRealFabrics) {
  for (const std::string& name : material_preset_names()) {
    const Material m = preset(name);
    for (const double b : {m.bending, m.bending_warp}) {
      const double c = bending_length(b, m.density);
      EXPECT_GE(c, 0.005) << name << ": bending length " << c << " m";
      EXPECT_LE(c, 0.05) << name << ": bending length " << c << " m";
    }
  }
}

TEST(MaterialPresets, SilkIsLimpestAndLinenStiffestInBending) {
  const Material silk = preset("silk");
  const Material cotton = preset("cotton");
  const Material linen = preset("linen");
  EXPECT_LT(bending_length(silk.bending, silk.density),
            bending_length(cotton.bending, cotton.density));
  EXPECT_LT(bending_length(cotton.bending, cotton.density),
            bending_length(linen.bending, linen.density));
  EXPECT_LT(bending_length(silk.bending_warp, silk.density),
            bending_length(cotton.bending_warp, cotton.density));
  EXPECT_LT(bending_length(cotton.bending_warp, cotton.density),
            bending_length(linen.bending_warp, linen.density));
}

TEST(MaterialPresets, CottonMatchesItsSourceValues) {
  // Clyde et al. 2017 as transcribed in Codim-IPC: Pa x 0.18 mm, shear C3 h / 2.
  const Material m = preset("cotton");
  EXPECT_NEAR(m.density, 0.1036, 1e-12);
  EXPECT_NEAR(m.weft, 2800.26, 1e-6);
  EXPECT_NEAR(m.warp, 4500.72, 1e-6);
  EXPECT_NEAR(m.coupling, 1400.22, 1e-6);
  EXPECT_NEAR(m.shear, 96.84, 1e-6);
  // Bending length 1.65 cm as the geometric mean of weft and warp.
  EXPECT_NEAR(bending_length(std::sqrt(m.bending * m.bending_warp), m.density), 0.0165, 1e-9);
}

}  // namespace
}  // namespace tissu
