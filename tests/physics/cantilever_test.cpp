// Peirce's cantilever against the elastica: the bending model gives back the rigidity B the
// scene declares, on any mesh (docs/bending.md).
#include "physics/cantilever.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>

#include "mesh/load.h"
#include "mesh/mesh_test_util.h"
#include "mesh/obj_writer.h"

namespace tissu {
namespace {

using testing::CantileverSetup;
using testing::StripMesh;

constexpr double kDeg = 180.0 / kPi;

TEST(Elastica, PeirceChordAngleAtTwiceTheBendingLength) {
  // Peirce (1930): c = l (cos(theta/2) / (8 tan theta))^(1/3); theta = 41.5 deg at l = 2c.
  const double theta = testing::elastica_chord_angle(8.0);
  EXPECT_NEAR(theta * kDeg, 41.5, 0.3);
}

struct MeshCase {
  const char* name;
  StripMesh kind;
  double width;  // m
};
// The meshes of Peirce's strip, 1 mm cells along it.
const MeshCase kMeshes[] = {{"union_jack_2_across", StripMesh::UnionJack, 0.002},
                            {"union_jack_10_across", StripMesh::UnionJack, 0.010},
                            {"one_diagonal_10_across", StripMesh::OneDiagonal, 0.010},
                            {"irregular_10_across", StripMesh::Irregular, 0.010}};
constexpr double kLength = 0.05;  // overhang, m
constexpr double kCell = 0.001;   // m
constexpr double kToleranceDeg = 0.5;

// The setup whose bending length is kLength / ratio: B = rho_A g c^3.
CantileverSetup setup_for(double ratio) {
  CantileverSetup setup;
  const double c = kLength / ratio;
  setup.bending_weft = setup.density * setup.gravity * c * c * c;
  return setup;
}

double elastica_deg(const CantileverSetup& setup, double B) {
  const double w = setup.density * setup.gravity;
  return testing::elastica_chord_angle(w * kLength * kLength * kLength / B) * kDeg;
}

// Rigidity of a narrow strip cut at angle phi from the weft, free to twist and to curve
// across (moments other than the bending one are zero): 1 / (D'^-1)_11 with D' the plate
// constants D11 = B_weft, D22 = B_warp, D12 = 0, D66 = (B_weft + B_warp) / 4 turned to the
// strip's axes, curvatures (k11, k22, 2 k12) transforming like strains.
double narrow_strip_rigidity(double B_weft, double B_warp, double phi) {
  const double c = std::cos(phi), s = std::sin(phi);
  Eigen::Matrix3d D = Eigen::Vector3d(B_weft, B_warp, (B_weft + B_warp) / 4).asDiagonal();
  Eigen::Matrix3d T;
  T << c * c, s * s, c * s, s * s, c * c, -c * s, -2 * c * s, 2 * c * s, c * c - s * s;
  const Eigen::Matrix3d T_inv = T.inverse();
  const Eigen::Matrix3d D_strip = T_inv.transpose() * D * T_inv;
  return 1.0 / D_strip.inverse()(0, 0);
}

class CantileverOnMesh : public ::testing::TestWithParam<MeshCase> {};

// Overhang 1, 2 and 3 bending lengths: from nearly linear to large rotation.
TEST_P(CantileverOnMesh, MatchesTheElasticaAtSeveralOverhangs) {
  const MeshCase& mesh = GetParam();
  const auto strip = testing::make_strip(mesh.kind, kLength, mesh.width, kCell, 3);
  for (double ratio : {1.0, 2.0, 3.0}) {
    const CantileverSetup setup = setup_for(ratio);
    const auto r = testing::solve_cantilever(strip, setup);
    const double expected = elastica_deg(setup, setup.bending_weft);
    std::printf("  %s, overhang %.0f c: elastica %.2f deg, Tissu %.2f deg\n", mesh.name, ratio,
                expected, r.chord_angle * kDeg);
    EXPECT_TRUE(r.converged);
    EXPECT_NEAR(r.chord_angle * kDeg, expected, kToleranceDeg) << "overhang " << ratio << " c";
  }
}

INSTANTIATE_TEST_SUITE_P(Meshes, CantileverOnMesh, ::testing::ValuesIn(kMeshes),
                         [](const auto& info) { return std::string(info.param.name); });

TEST(Cantilever, RefinementChangesTheAngleLessThanTheTolerance) {
  const CantileverSetup setup = setup_for(2.0);
  double angle[2];
  for (int level = 0; level < 2; ++level) {
    const double cell = 0.002 / (1 << level);
    const auto strip = testing::make_strip(StripMesh::UnionJack, kLength, 0.004, cell, 3);
    const auto r = testing::solve_cantilever(strip, setup);
    ASSERT_TRUE(r.converged);
    angle[level] = r.chord_angle * kDeg;
  }
  std::printf("  2 mm cells %.2f deg, 1 mm cells %.2f deg\n", angle[0], angle[1]);
  EXPECT_LT(std::abs(angle[1] - angle[0]), kToleranceDeg);
}

// Peirce's strip written to a file with Tissu's OBJ writer (and as an ASCII PLY, read
// through assimp), read back with the loader a scene uses, bends as the elastica says: a
// mesh read from a file is no different from a generated one.
std::string write_strip_ply(const std::string& path, const testing::Strip& strip) {
  std::ofstream out(path);
  out << "ply\nformat ascii 1.0\nelement vertex " << strip.st.size()
      << "\nproperty double x\nproperty double y\nproperty double z\nelement face "
      << strip.triangles.size() << "\nproperty list uchar int vertex_indices\nend_header\n";
  out.precision(17);
  for (const Vec2& p : strip.st) out << p.x() << " " << p.y() << " 0\n";
  for (const Tri& t : strip.triangles) out << "3 " << t[0] << " " << t[1] << " " << t[2] << "\n";
  return path;
}

TEST(Cantilever, MeshReadFromAFileMatchesTheElastica) {
  const CantileverSetup setup = setup_for(2.0);
  const double expected = elastica_deg(setup, setup.bending_weft);
  test::TempDir dir;
  for (StripMesh kind : {StripMesh::UnionJack, StripMesh::Irregular}) {
    const auto strip = testing::make_strip(kind, kLength, 0.004, kCell, 3);
    Vec3List positions;
    for (const Vec2& p : strip.st) positions.emplace_back(p.x(), p.y(), 0.0);
    write_obj(dir.file("strip.obj"), positions, strip.st, strip.triangles);
    for (const std::string& file :
         {dir.file("strip.obj"), write_strip_ply(dir.file("strip.ply"), strip)}) {
      const TriMesh mesh = load_mesh(file, 1.0);
      ASSERT_EQ(mesh.rest_uv.size(), strip.st.size()) << file;
      testing::Strip loaded = strip;
      loaded.st = mesh.rest_uv;  // s and t as the file gives them back
      loaded.triangles = mesh.triangles;
      const auto r = testing::solve_cantilever(loaded, setup);
      std::printf("  %s, %s: elastica %.2f deg, Tissu %.2f deg\n",
                  kind == StripMesh::UnionJack ? "union jack" : "irregular",
                  file.substr(file.size() - 3).c_str(), expected, r.chord_angle * kDeg);
      EXPECT_TRUE(r.converged) << file;
      EXPECT_NEAR(r.chord_angle * kDeg, expected, kToleranceDeg) << file;
    }
  }
}

// The same strip with its rest coordinates rotated in the plane (an isotropic fabric):
// the same angle, whatever the direction of the mesh's edges.
TEST(Cantilever, RotatingTheMeshInItsPlaneChangesNothing) {
  CantileverSetup setup = setup_for(2.0);
  const auto strip = testing::make_strip(StripMesh::UnionJack, kLength, 0.004, kCell, 3);
  const double straight = testing::solve_cantilever(strip, setup).chord_angle * kDeg;
  setup.fabric_angle = 0.7;
  const double rotated = testing::solve_cantilever(strip, setup).chord_angle * kDeg;
  EXPECT_NEAR(rotated, straight, 0.05);
}

// Warp three times as stiff as weft: a strip cut along the weft bends with B_weft, along the
// warp with B_warp, on structured and irregular meshes alike. On the bias an orthotropic
// strip also twists (docs/bending.md), so its angle lies between the plate law B(phi) =
// B_weft cos^2 phi + B_warp sin^2 phi (twist held) and the narrow strip free to twist.
TEST(Cantilever, WeftAndWarpStayDistinctOnAnyMesh) {
  CantileverSetup setup = setup_for(2.0);
  const double B_weft = setup.bending_weft, B_warp = 3.0 * B_weft;
  setup.bending_warp = B_warp;
  for (StripMesh kind : {StripMesh::UnionJack, StripMesh::Irregular}) {
    const auto strip = testing::make_strip(kind, kLength, 0.004, kCell, 3);
    setup.fabric_angle = 0.0;
    EXPECT_NEAR(testing::solve_cantilever(strip, setup).chord_angle * kDeg,
                elastica_deg(setup, B_weft), kToleranceDeg);
    setup.fabric_angle = kPi / 2;
    EXPECT_NEAR(testing::solve_cantilever(strip, setup).chord_angle * kDeg,
                elastica_deg(setup, B_warp), kToleranceDeg);
    setup.fabric_angle = kPi / 4;
    const double bias = testing::solve_cantilever(strip, setup).chord_angle * kDeg;
    const double B_free_twist = narrow_strip_rigidity(B_weft, B_warp, kPi / 4);
    const double B_plate = 0.5 * (B_weft + B_warp);
    std::printf("  bias 45 deg: plate law %.2f deg, free twist %.2f deg, Tissu %.2f deg\n",
                elastica_deg(setup, B_plate), elastica_deg(setup, B_free_twist), bias);
    EXPECT_GT(bias, elastica_deg(setup, B_plate));
    EXPECT_LT(bias, elastica_deg(setup, B_free_twist) + kToleranceDeg);
  }
}

}  // namespace
}  // namespace tissu
