// load_mesh on small files written into a temporary directory: vertex order, rest (u, v),
// other formats through assimp, and one test per class of bad input.
#include "mesh/load.h"

#include <gtest/gtest.h>

#include "mesh/quality.h"
#include "mesh_test_util.h"

namespace tissu {
namespace {

using test::input_error_of;
using test::kSquarePly;

class meshLoad : public testing::Test {
 protected:
  // Writes `text` as `name` and returns the error load_mesh raises ("" for none).
  std::string error_loading(const std::string& name, const std::string& text,
                            double uv_scale = 1.0) {
    const std::string path = dir_.write(name, text);
    return input_error_of([&] { load_mesh(path, uv_scale); });
  }
  std::string path(const std::string& name) const { return dir_.file(name); }

  test::TempDir dir_;
};

// Four corners of the unit square in the file order (0,0) (1,1) (1,0) (0,1); the faces use
// them out of order. Ids 0..3 must follow the v lines, not the faces.
const char kShuffledSquare[] =
    "# a unit square\n"
    "v 0 0 0\n"
    "v 1 1 0\n"
    "v 1 0 0\n"
    "v 0 1 0\n"
    "f 4 1 3\n"
    "f 4 3 2\n";

TEST_F(meshLoad, KeepsTheFilesVertexOrder) {
  const TriMesh mesh = load_mesh(dir_.write("square.obj", kShuffledSquare), 1.0);
  ASSERT_EQ(mesh.positions.size(), 4u);
  EXPECT_EQ(mesh.positions[0], Vec3(0, 0, 0));
  EXPECT_EQ(mesh.positions[1], Vec3(1, 1, 0));
  EXPECT_EQ(mesh.positions[2], Vec3(1, 0, 0));
  EXPECT_EQ(mesh.positions[3], Vec3(0, 1, 0));
  EXPECT_EQ(mesh.triangles, (TriList{{3, 0, 2}, {3, 2, 1}}));
}

TEST_F(meshLoad, FlatMeshWithoutTextureIsProjectedOntoItsPlane) {
  const TriMesh mesh = load_mesh(dir_.write("square.obj", kShuffledSquare), 1.0);
  EXPECT_FALSE(mesh.uv_from_file);
  for (size_t i = 0; i < 4; ++i) {  // x-y plane facing +z: (u, v) = (x, y)
    EXPECT_NEAR(mesh.rest_uv[i].x(), mesh.positions[i].x(), 1e-15);
    EXPECT_NEAR(mesh.rest_uv[i].y(), mesh.positions[i].y(), 1e-15);
  }
}

TEST_F(meshLoad, TiltedFlatMeshKeepsItsShapeInUV) {
  // The unit square rotated 90 deg about x (into the x-z plane) and shifted.
  const TriMesh mesh = load_mesh(dir_.write("tilted.obj",
                                            "v 2 5 0\nv 3 5 0\nv 3 5 1\nv 2 5 1\n"
                                            "f 1 2 3\nf 1 3 4\n"),
                                 1.0);
  const MeshQuality q = measure_quality(mesh);
  EXPECT_NEAR(q.total_area, 1.0, 1e-12);  // m^2
  EXPECT_NEAR((mesh.rest_uv[1] - mesh.rest_uv[0]).norm(), 1.0, 1e-12);
  EXPECT_NEAR((mesh.rest_uv[1] - mesh.rest_uv[0]).x(), 1.0, 1e-12);  // u along world x
}

TEST_F(meshLoad, TextureCoordinatesTimesUVScaleBecomeRestUV) {
  // vt lines in cm and in another order than the v lines; the positions are draped (not flat).
  const TriMesh mesh = load_mesh(dir_.write("draped.obj",
                                            "v 0 0 0\nv 1 1 0.3\nv 1 0 0.2\nv 0 1 0.1\n"
                                            "vt 0 100\nvt 100 0\nvt 0 0\nvt 100 100\n"
                                            "f 4/1 1/3 3/2\nf 4/1 3/2 2/4\n"),
                                 0.01);
  EXPECT_TRUE(mesh.uv_from_file);
  EXPECT_EQ(mesh.rest_uv[0], Vec2(0, 0));
  EXPECT_EQ(mesh.rest_uv[1], Vec2(1, 1));
  EXPECT_EQ(mesh.rest_uv[2], Vec2(1, 0));
  EXPECT_EQ(mesh.rest_uv[3], Vec2(0, 1));
  EXPECT_EQ(mesh.positions[1], Vec3(1, 1, 0.3));
}

TEST_F(meshLoad, ReadsNegativeIndicesPolygonsAndAllCornerForms) {
  const std::string text =
      "o cloth\r\n"
      "mtllib cloth.mtl\r\n"
      "v 0 0 0\r\n"
      "v 1 0 0\r\n"
      "v 1 1 0\r\n"
      "v 0 1 0\r\n"
      "vt 0 0\r\nvt 1 0\r\nvt 1 1\r\nvt 0 1\r\n"
      "vn 0 0 1\r\n"
      "g part\r\ns off\r\nusemtl cotton\r\n"
      "f 1/1/1 2/2/1 3/3/1 4/4/1  # a quad\r\n"
      "\r\n"
      "v 2 0 0\r\n"
      "vt 2 0\r\n"
      "f -4/-4/1 -1/-1/1 -3/-3/1\r\n";
  const TriMesh mesh = load_mesh(dir_.write("forms.obj", text), 1.0);
  EXPECT_EQ(mesh.triangles, (TriList{{0, 1, 2}, {0, 2, 3}, {1, 4, 2}}));
  EXPECT_EQ(mesh.rest_uv[4], Vec2(2, 0));

  const TriMesh normals_only =
      load_mesh(dir_.write("vn.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//1\n"), 1.0);
  EXPECT_EQ(normals_only.triangles, (TriList{{0, 1, 2}}));
  EXPECT_FALSE(normals_only.uv_from_file);
}

TEST_F(meshLoad, DuplicatePositionsStayDistinctVertices) {
  // Two squares side by side that share positions but not vertices (a cut in the cloth).
  const TriMesh mesh = load_mesh(dir_.write("cut.obj",
                                            "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                                            "v 1 0 0\nv 2 0 0\nv 2 1 0\nv 1 1 0\n"
                                            "f 1 2 3\nf 1 3 4\nf 5 6 7\nf 5 7 8\n"),
                                 1.0);
  EXPECT_EQ(mesh.positions.size(), 8u);
  EXPECT_EQ(mesh.triangles[2], Tri(4, 5, 6));
}

TEST_F(meshLoad, OtherFormatsGoThroughAssimpAndAreWelded) {
  // ASCII STL stores each corner separately: 6 corners weld into 4 vertices.
  const std::string stl =
      "solid square\n"
      "facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 1 1 0\nendloop\nendfacet\n"
      "facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 1 0\nvertex 0 1 0\nendloop\nendfacet\n"
      "endsolid square\n";
  const TriMesh mesh = load_mesh(dir_.write("square.stl", stl), 1.0);
  EXPECT_EQ(mesh.positions.size(), 4u);
  EXPECT_EQ(mesh.triangles, (TriList{{0, 1, 2}, {0, 2, 3}}));
  EXPECT_EQ(mesh.positions[3], Vec3(0, 1, 0));
  EXPECT_NEAR(measure_quality(mesh).total_area, 1.0, 1e-12);
}

TEST_F(meshLoad, SameGridHasTheSameIdsAsObjAndPlyAndStlIsMarkedWelded) {
  // A 3 x 2 grid whose faces use the vertices out of their file order.
  const char* positions[] = {"0 0 0", "1 0 0", "2 0 0", "0 1 0", "1 1 0", "2 1 0"};
  const int faces[4][3] = {{1, 2, 5}, {1, 5, 4}, {0, 1, 4}, {0, 4, 3}};
  std::string obj, ply = "ply\nformat ascii 1.0\nelement vertex 6\nproperty float x\n"
                         "property float y\nproperty float z\nelement face 4\n"
                         "property list uchar int vertex_indices\nend_header\n";
  std::string stl = "solid grid\n";
  for (const char* p : positions) {
    obj += std::string("v ") + p + "\n";
    ply += std::string(p) + "\n";
  }
  for (const auto& f : faces) {
    obj += "f " + std::to_string(f[0] + 1) + " " + std::to_string(f[1] + 1) + " " +
           std::to_string(f[2] + 1) + "\n";
    ply += "3 " + std::to_string(f[0]) + " " + std::to_string(f[1]) + " " +
           std::to_string(f[2]) + "\n";
    stl += "facet normal 0 0 1\nouter loop\n";
    for (int k = 0; k < 3; ++k) stl += std::string("vertex ") + positions[f[k]] + "\n";
    stl += "endloop\nendfacet\n";
  }
  stl += "endsolid grid\n";
  const TriMesh from_obj = load_mesh(dir_.write("grid.obj", obj), 1.0);
  const TriMesh from_ply = load_mesh(dir_.write("grid.ply", ply), 1.0);
  const TriMesh from_stl = load_mesh(dir_.write("grid.stl", stl), 1.0);
  ASSERT_EQ(from_obj.positions.size(), 6u);
  EXPECT_EQ(from_ply.positions, from_obj.positions);
  EXPECT_EQ(from_ply.triangles, from_obj.triangles);
  EXPECT_TRUE(from_obj.file_vertex_ids);
  EXPECT_TRUE(from_ply.file_vertex_ids);
  // STL has no vertex list: its corners are welded in order of appearance, and the mesh
  // says its ids are not the file's (pins by id are refused, see scene_test).
  EXPECT_EQ(from_stl.positions.size(), 6u);
  EXPECT_NE(from_stl.positions, from_obj.positions);
  EXPECT_FALSE(from_stl.file_vertex_ids);
}

TEST_F(meshLoad, AssimpFormatTextureCoordinatesAreUsed) {
  const TriMesh mesh = load_mesh(dir_.write("square.ply", kSquarePly), 0.5);
  EXPECT_TRUE(mesh.uv_from_file);
  ASSERT_EQ(mesh.positions.size(), 4u);
  EXPECT_EQ(mesh.positions[0], Vec3(0, 0, 0.5));
  EXPECT_EQ(mesh.rest_uv[2], Vec2(1, 1));
  EXPECT_NEAR(measure_quality(mesh).total_area, 1.0, 1e-12);
}

// --- bad input: one line naming the file and the place ---

TEST_F(meshLoad, MissingFile) {
  EXPECT_EQ(input_error_of([&] { load_mesh(path("absent.obj"), 1.0); }),
            path("absent.obj") + ": cannot open: No such file or directory");
  EXPECT_EQ(input_error_of([&] { load_mesh(dir_.path().string(), 1.0); }),
            dir_.path().string() + ": cannot open: not a regular file");
}

TEST_F(meshLoad, FormatAssimpCannotRead) {
  const std::string message = error_loading("cloth.nonsense", "this is not a mesh\n");
  EXPECT_EQ(message.rfind(path("cloth.nonsense") + ": cannot read this format or file: ", 0), 0u)
      << message;
}

TEST_F(meshLoad, NoTriangles) {
  EXPECT_EQ(error_loading("empty.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n"),
            path("empty.obj") + ": contains no triangles");
}

TEST_F(meshLoad, VertexIndexOutOfRange) {
  EXPECT_EQ(error_loading("range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 3 40\n"),
            path("range.obj") + ": line 5 (face 2): vertex index 40 out of range (file has 3 vertices)");
  EXPECT_EQ(error_loading("negative.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\n"),
            path("negative.obj") + ": line 4 (face 1): vertex index -4 out of range (file has 3 vertices)");
}

TEST_F(meshLoad, UnreadableIndexOrNumber) {
  EXPECT_EQ(error_loading("zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n"),
            path("zero.obj") + ": line 4 (face 1): cannot read '0' as a vertex index");
  EXPECT_EQ(error_loading("word.obj", "v 0 0 0\nv 1 zero 0\n"),
            path("word.obj") + ": line 2: cannot read 'zero' as a number");
  EXPECT_EQ(error_loading("short.obj", "v 0 0\n"),
            path("short.obj") + ": line 1: a v statement needs 3 coordinates");
  EXPECT_EQ(error_loading("edge.obj", "v 0 0 0\nv 1 0 0\nf 1 2\n"),
            path("edge.obj") + ": line 3 (face 1): a face needs at least 3 vertices, got 2");
}

TEST_F(meshLoad, NonFiniteCoordinates) {
  EXPECT_EQ(error_loading("nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n"),
            path("nan.obj") + ": line 2: non-finite coordinate 'nan'");
  EXPECT_EQ(error_loading("inf.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt -inf 0\nf 1/1 2/1 3/1\n"),
            path("inf.obj") + ": line 4: non-finite coordinate '-inf'");
}

TEST_F(meshLoad, DuplicateTrianglesAreDroppedWithAWarning) {
  testing::internal::CaptureStderr();
  const TriMesh mesh = load_mesh(
      dir_.write("dup.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 3\nf 2 3 1\n"), 1.0);
  EXPECT_EQ(testing::internal::GetCapturedStderr(),
            "warning: " + path("dup.obj") +
                ": dropped 1 duplicate triangle (first: line 5 (face 2) repeats line 4 (face 1))\n");
  EXPECT_EQ(mesh.triangles.size(), 1u);
}

TEST_F(meshLoad, ZeroAreaTriangles) {
  EXPECT_EQ(error_loading("flat3d.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nf 1 2 4\nf 1 2 3\n"),
            path("flat3d.obj") + ": line 6 (face 2): zero area in 3D (vertex ids 0, 1, 2, area 0 m^2)");
  EXPECT_EQ(error_loading("flatuv.obj",
                          "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 1\nvt 2 2\nf 1/1 2/2 3/3\n"),
            path("flatuv.obj") + ": line 7 (face 1): zero area in (u, v) (vertex ids 0, 1, 2, area 0 m^2)");
  EXPECT_EQ(error_loading("repeat.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 2\n"),
            path("repeat.obj") + ": line 5 (face 2): uses a vertex twice (vertex ids 0, 1, 1)");
}

TEST_F(meshLoad, UnusedVerticesAreKeptWithAWarning) {
  testing::internal::CaptureStderr();
  const TriMesh mesh =
      load_mesh(dir_.write("unused.obj", "v 0 0 0\nv 9 9 0\nv 1 0 0\nv 0 1 0\nf 1 3 4\n"), 1.0);
  EXPECT_EQ(testing::internal::GetCapturedStderr(),
            "warning: " + path("unused.obj") +
                ": 1 vertex is used by no triangle (first: vertex id 1); kept\n");
  EXPECT_EQ(mesh.positions.size(), 4u);
}

TEST_F(meshLoad, TextureSeamsAreRejected) {
  EXPECT_EQ(error_loading("seam.obj",
                          "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                          "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvt 5 5\n"
                          "f 1/1 2/2 3/3\nf 1/1 3/5 4/4\n"),
            path("seam.obj") +
                ": line 11 (face 2): vertex index 3 has texture coordinates (5, 5) here but (1, 1) at "
                "line 10 (face 1); UV seams are not supported, the rest shape needs one (u, v) per "
                "vertex: give each side of the seam its own vertex, or remove the texture coordinates");
}

TEST_F(meshLoad, TextureIndicesMustBeCompleteAndInRange) {
  EXPECT_EQ(error_loading("mixed.obj",
                          "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\n"
                          "f 1/1 2/2 3/3\nf 1 3 4\n"),
            path("mixed.obj") +
                ": line 9 (face 2): a corner has no texture coordinate index, unlike line 8 (face 1) "
                "(give every face corner a vt index, or none)");
  EXPECT_EQ(error_loading("vtrange.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nvt 0 0\nf 1/1 2/2 3/1\n"),
            path("vtrange.obj") +
                ": line 5 (face 1): texture coordinate index 2 out of range (file has 1 texture "
                "coordinates)");
}

TEST_F(meshLoad, CurvedMeshWithoutTextureIsRejected) {
  // Vertex 3 (id 2) is lifted 0.2 m; the mean plane tilts, and it stays the farthest.
  EXPECT_EQ(error_loading("curved.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0.2\nv 0 1 0\nf 1 2 3\nf 1 3 4\n"),
            path("curved.obj") +
                ": no texture coordinates and not flat: vertex id 2 is 0.0495074 m from the mean "
                "plane (tolerance 1.42829e-06 m): give the file texture coordinates (in m, or "
                "scaled by uv_scale) or a flat rest shape");
}

TEST_F(meshLoad, ClockwiseTextureIsReversedWithAWarning) {
  testing::internal::CaptureStderr();
  const TriMesh mesh = load_mesh(
      dir_.write("mirror.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt -1 0\nvt 0 1\nf 1/1 2/2 3/3\n"),
      1.0);
  EXPECT_EQ(testing::internal::GetCapturedStderr(),
            "warning: " + path("mirror.obj") +
                ": all triangles are clockwise in (u, v); reversed them all\n");
  EXPECT_EQ(mesh.triangles[0], Tri(0, 2, 1));
}

TEST_F(meshLoad, UVScaleMustBePositive) {
  const std::string file = dir_.write("square.obj", kShuffledSquare);
  EXPECT_EQ(input_error_of([&] { load_mesh(file, 0.0); }), file + ": uv_scale must be positive, got 0");
}

}  // namespace
}  // namespace tissu

namespace tissu {
namespace {

// A tetrahedron: OBJ with texture seams (ignored for surfaces), OFF and ASCII STL.
TEST_F(meshLoad, SurfacesReadAnyFormatWithoutRestCoordinates) {
  const std::string obj = dir_.write("tet.obj",
                                     "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"
                                     "vt 0 0\nvt 1 0\nvt 9 9\n"
                                     "f 1/1 3/2 2/3\nf 1/2 2/1 4/3\nf 1/3 4/2 3/1\nf 2 3 4\n");
  const SurfaceFile a = load_surface(obj);
  EXPECT_EQ(a.positions.size(), 4u);
  ASSERT_EQ(a.triangles.size(), 4u);
  EXPECT_EQ(a.triangles[0], Tri(0, 2, 1));
  EXPECT_EQ(a.places[3], "line 11 (face 4)");
  const std::string off = dir_.write("tet.off",
                                     "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n"
                                     "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n");
  const SurfaceFile b = load_surface(off);
  EXPECT_EQ(b.positions.size(), 4u);
  EXPECT_EQ(b.triangles.size(), 4u);
  std::string stl = "solid tet\n";
  const char* facets[4] = {"0 0 0  0 1 0  1 0 0", "0 0 0  1 0 0  0 0 1",
                           "0 0 0  0 0 1  0 1 0", "1 0 0  0 1 0  0 0 1"};
  for (const char* f : facets) {
    double v[9];
    std::sscanf(f, "%lf %lf %lf %lf %lf %lf %lf %lf %lf", &v[0], &v[1], &v[2], &v[3], &v[4],
                &v[5], &v[6], &v[7], &v[8]);
    stl += "facet normal 0 0 0\nouter loop\n";
    for (int k = 0; k < 3; ++k) {
      stl += "vertex " + std::to_string(v[3 * k]) + " " + std::to_string(v[3 * k + 1]) + " " +
             std::to_string(v[3 * k + 2]) + "\n";
    }
    stl += "endloop\nendfacet\n";
  }
  stl += "endsolid tet\n";
  const SurfaceFile c = load_surface(dir_.write("tet.stl", stl));
  EXPECT_EQ(c.positions.size(), 4u);  // corners welded
  EXPECT_EQ(c.triangles.size(), 4u);
  EXPECT_EQ(input_error_of([&] { load_surface(path("missing.off")); }),
            path("missing.off") + ": cannot open: No such file or directory");
}

}  // namespace
}  // namespace tissu
