// write_obj: exact round trip through load_mesh, file layout, and atomic failure.
#include "mesh/obj_writer.h"

#include <gtest/gtest.h>

#include <sys/stat.h>

#include <cmath>
#include <iterator>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/error.h"
#include "core/partial_file.h"
#include "mesh/generate.h"
#include "mesh/load.h"
#include "mesh_test_util.h"

namespace tissu {
namespace {

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

TEST(meshObjWriter, RoundTripKeepsOrderPositionsAndUVExactly) {
  test::TempDir dir;
  TriMesh mesh = generate_rectangle(0.7, 0.3, 990, true, 11);
  for (Vec3& p : mesh.positions) {  // a deformed frame: values with all 17 digits in use
    p.z() = 0.1 * std::sin(7.3 * p.x()) + 1e-7 / 3.0;
    p.x() *= 1.0 + 1.0 / 3.0;
  }
  const std::string path = dir.file("frame.obj");
  write_obj(path, mesh.positions, mesh.rest_uv, mesh.triangles);
  const TriMesh loaded = load_mesh(path, 1.0);
  EXPECT_TRUE(loaded.uv_from_file);
  EXPECT_EQ(loaded.positions, mesh.positions);
  EXPECT_EQ(loaded.rest_uv, mesh.rest_uv);
  EXPECT_EQ(loaded.triangles, mesh.triangles);
}

TEST(meshObjWriter, WritesVVtAndOneBasedFaces) {
  test::TempDir dir;
  const std::string path = dir.file("tri.obj");
  write_obj(path, {Vec3(0, 0, 0), Vec3(1.5, 0, 0), Vec3(0, 0.1, 2)},
            {Vec2(0, 0), Vec2(1.5, 0), Vec2(0, 0.25)}, {Tri(0, 1, 2)});
  EXPECT_EQ(read_text(path),
            "# written by tissu: positions in m, vt = rest (u, v) in m\n"
            "v 0 0 0\nv 1.5 0 0\nv 0 0.1 2\n"
            "vt 0 0\nvt 1.5 0\nvt 0 0.25\n"
            "f 1/1 2/2 3/3\n");
  EXPECT_FALSE(std::filesystem::exists(partial_path_for(path)));
}

TEST(meshObjWriter, WithoutRestUVWritesPlainFaces) {
  test::TempDir dir;
  const std::string path = dir.file("plain.obj");
  write_obj(path, {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)}, {}, {Tri(0, 1, 2)});
  EXPECT_NE(read_text(path).find("\nf 1 2 3\n"), std::string::npos);
  EXPECT_EQ(read_text(path).find("\nvt"), std::string::npos);
}

TEST(meshObjWriter, MissingDirectoryThrowsAndLeavesNothing) {
  test::TempDir dir;
  const std::string path = dir.file("absent/frame.obj");
  try {
    write_obj(path, {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)}, {}, {Tri(0, 1, 2)});
    FAIL() << "no OutputError";
  } catch (const OutputError& e) {
    EXPECT_EQ(std::string(e.what()), path + ": cannot write: No such file or directory");
  }
  EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
}

// A directory in the way makes the final rename fail: the temporary file must go, and what
// was at the path stays as it was.
TEST(meshObjWriter, FailedRenameRemovesTheTemporaryFile) {
  test::TempDir dir;
  const std::string path = dir.file("taken");
  std::filesystem::create_directory(path);
  std::ofstream(path + "/keep") << "x";
  EXPECT_THROW(write_obj(path, {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)}, {}, {Tri(0, 1, 2)}),
               OutputError);
  EXPECT_FALSE(std::filesystem::exists(partial_path_for(path)));
  EXPECT_TRUE(std::filesystem::exists(path + "/keep"));
}

// A named pipe at the path is refused, never replaced, and the temporary file goes.
TEST(meshObjWriter, RefusesAPathThatIsNotARegularFile) {
  test::TempDir dir;
  const std::string path = dir.file("frame_000000.obj");
  ASSERT_EQ(mkfifo(path.c_str(), 0644), 0);
  try {
    write_obj(path, {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)}, {}, {Tri(0, 1, 2)});
    ADD_FAILURE() << "no error";
  } catch (const OutputError& e) {
    EXPECT_EQ(std::string(e.what()), path + ": cannot write: not a regular file (named pipe)");
  }
  EXPECT_TRUE(std::filesystem::is_fifo(path));
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir.path()),
                          std::filesystem::directory_iterator()),
            1);
}

// An existing file is replaced whole.
TEST(meshObjWriter, ReplacesAnExistingFile) {
  test::TempDir dir;
  const std::string path = dir.write("frame.obj", "old contents that are longer than the new ones\n"
                                                  "old contents that are longer than the new ones\n"
                                                  "old contents that are longer than the new ones\n");
  write_obj(path, {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)}, {}, {Tri(0, 1, 2)});
  EXPECT_EQ(read_text(path).find("old"), std::string::npos);
  EXPECT_EQ(load_mesh(path, 1.0).triangles.size(), 1u);
}

TEST(meshObjWriter, RejectsInconsistentInput) {
  test::TempDir dir;
  EXPECT_THROW(write_obj(dir.file("a.obj"), {Vec3(0, 0, 0)}, {Vec2(0, 0), Vec2(1, 0)}, {}),
               std::invalid_argument);
  EXPECT_THROW(write_obj(dir.file("b.obj"), {Vec3(0, 0, 0)}, {}, {Tri(0, 1, 2)}),
               std::invalid_argument);
  EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
}

}  // namespace
}  // namespace tissu
