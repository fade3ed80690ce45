// validate_mesh: each class of bad mesh is rejected or repaired with the expected message.
#include "mesh/validate.h"

#include <gtest/gtest.h>

#include <cmath>

#include "mesh_test_util.h"

namespace tissu {
namespace {

using test::input_error_of;

// Two triangles forming the unit square, counter-clockwise, in the z = 0 plane.
TriMesh unit_square() {
  TriMesh mesh;
  mesh.rest_uv = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  for (const Vec2& p : mesh.rest_uv) mesh.positions.emplace_back(p.x(), p.y(), 0.0);
  mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  return mesh;
}

std::string error_of(TriMesh mesh) {
  return input_error_of([&] { validate_mesh(mesh, "cloth.obj"); });
}

TEST(meshValidate, AcceptsAGoodMeshSilently) {
  TriMesh mesh = unit_square();
  testing::internal::CaptureStderr();
  validate_mesh(mesh, "cloth.obj");
  EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
  EXPECT_EQ(mesh.triangles.size(), 2u);
}

TEST(meshValidate, RejectsNoTriangles) {
  TriMesh mesh = unit_square();
  mesh.triangles.clear();
  EXPECT_EQ(error_of(mesh), "cloth.obj: contains no triangles");
}

TEST(meshValidate, RejectsVertexIdOutOfRange) {
  TriMesh mesh = unit_square();
  mesh.triangles[1][2] = 4;
  EXPECT_EQ(error_of(mesh), "cloth.obj: triangle 1: vertex id 4 out of range (mesh has 4 vertices)");
  mesh.triangles[1][2] = -1;
  EXPECT_EQ(error_of(mesh), "cloth.obj: triangle 1: vertex id -1 out of range (mesh has 4 vertices)");
}

TEST(meshValidate, RejectsARepeatedVertex) {
  TriMesh mesh = unit_square();
  mesh.triangles[0] = Tri(0, 1, 1);
  EXPECT_EQ(error_of(mesh), "cloth.obj: triangle 0: uses a vertex twice (vertex ids 0, 1, 1)");
}

TEST(meshValidate, RejectsNonFiniteCoordinates) {
  TriMesh mesh = unit_square();
  mesh.positions[2].y() = NAN;
  EXPECT_EQ(error_of(mesh), "cloth.obj: vertex id 2: non-finite position (1, nan, 0)");
  mesh = unit_square();
  mesh.rest_uv[3].x() = INFINITY;
  EXPECT_EQ(error_of(mesh), "cloth.obj: vertex id 3: non-finite rest coordinates (inf, 1)");
}

TEST(meshValidate, RejectsZeroAreaIn3D) {
  TriMesh mesh = unit_square();
  mesh.positions[3] = mesh.positions[0] + 0.5 * (mesh.positions[2] - mesh.positions[0]);
  EXPECT_EQ(error_of(mesh), "cloth.obj: triangle 1: zero area in 3D (vertex ids 0, 2, 3, area 0 m^2)");
}

TEST(meshValidate, RejectsZeroAreaInUV) {
  TriMesh mesh = unit_square();
  mesh.rest_uv[1] = Vec2(0.5, 0.5);  // on the diagonal from (0, 0) to (1, 1)
  EXPECT_EQ(error_of(mesh), "cloth.obj: triangle 0: zero area in (u, v) (vertex ids 0, 1, 2, area 0 m^2)");
}

TEST(meshValidate, AcceptsTinyButNonZeroArea) {
  TriMesh mesh = unit_square();
  mesh.positions[1] = Vec3(1, 0.999999, 0);  // relative height 1e-6: far above rounding
  mesh.rest_uv[1] = Vec2(1, 0.999999);
  EXPECT_EQ(error_of(mesh), "");
}

TEST(meshValidate, RejectsMixedOrientationInUV) {
  TriMesh mesh = unit_square();
  mesh.triangles.emplace_back(2, 4, 3);  // a fold: the third triangle lies over the second
  mesh.rest_uv.emplace_back(0.5, 0.6);
  mesh.positions.emplace_back(0.5, 0.6, 0.5);
  EXPECT_EQ(error_of(mesh),
            "cloth.obj: triangle 2: clockwise in (u, v) but 2 of 3 triangles are the other way (the "
            "rest shape folds over itself or the triangles are inconsistently ordered)");
}

TEST(meshValidate, ReversesAllClockwiseTrianglesWithAWarning) {
  TriMesh mesh = unit_square();
  for (Tri& t : mesh.triangles) std::swap(t[1], t[2]);
  testing::internal::CaptureStderr();
  validate_mesh(mesh, "cloth.obj");
  EXPECT_EQ(testing::internal::GetCapturedStderr(),
            "warning: cloth.obj: all triangles are clockwise in (u, v); reversed them all\n");
  EXPECT_EQ(mesh.triangles, unit_square().triangles);
}

TEST(meshValidate, DropsDuplicateTrianglesWithAWarning) {
  TriMesh mesh = unit_square();
  mesh.triangles.emplace_back(2, 0, 1);  // triangle 0 again, rotated
  mesh.triangles.emplace_back(0, 2, 3);
  testing::internal::CaptureStderr();
  validate_mesh(mesh, "cloth.obj",
                {"line 5 (face 1)", "line 6 (face 2)", "line 7 (face 3)", "line 8 (face 4)"});
  EXPECT_EQ(testing::internal::GetCapturedStderr(),
            "warning: cloth.obj: dropped 2 duplicate triangles (first: line 7 (face 3) repeats "
            "line 5 (face 1))\n");
  EXPECT_EQ(mesh.triangles, unit_square().triangles);
}

TEST(meshValidate, KeepsUnusedVerticesWithAWarning) {
  TriMesh mesh = unit_square();
  mesh.positions.emplace_back(5, 5, 5);
  mesh.rest_uv.emplace_back(5, 5);
  testing::internal::CaptureStderr();
  validate_mesh(mesh, "cloth.obj");
  EXPECT_EQ(testing::internal::GetCapturedStderr(),
            "warning: cloth.obj: 1 vertex is used by no triangle (first: vertex id 4); kept\n");
  EXPECT_EQ(mesh.positions.size(), 5u);
}

TEST(meshValidate, NamesTrianglesByTheirPlaceWhenGiven) {
  TriMesh mesh = unit_square();
  mesh.triangles[1] = Tri(0, 0, 3);
  EXPECT_EQ(input_error_of([&] {
              validate_mesh(mesh, "cloth.obj", {"line 5 (face 1)", "line 6 (face 2)"});
            }),
            "cloth.obj: line 6 (face 2): uses a vertex twice (vertex ids 0, 0, 3)");
}

TEST(meshValidate, RejectsMismatchedLengths) {
  TriMesh mesh = unit_square();
  mesh.rest_uv.pop_back();
  EXPECT_EQ(error_of(mesh), "cloth.obj: 4 positions but 3 rest coordinates");
}

}  // namespace
}  // namespace tissu
