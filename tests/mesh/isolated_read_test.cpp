// read_with_assimp runs assimp in a child process with a time limit: valid files give the same
// result as the in-process read, a child that hangs or crashes becomes a one-line InputError
// naming the file (test hook TISSU_MESH_READ_TEST=hang|abort|segv, honoured only in the child).
#include <gtest/gtest.h>

#include <stdlib.h>
#include <sys/wait.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

#include "mesh/load.h"
#include "mesh/mesh_readers.h"
#include "mesh_test_util.h"

namespace tissu {
namespace {

using test::input_error_of;
using test::kSquarePly;

// Sets an environment variable for the life of the object.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const char* value) : name_(name) {
    if (const char* old = getenv(name)) {
      had_ = true;
      old_ = old;
    }
    setenv(name, value, 1);
  }
  ~ScopedEnv() {
    if (had_) {
      setenv(name_, old_.c_str(), 1);
    } else {
      unsetenv(name_);
    }
  }

 private:
  const char* name_;
  bool had_ = false;
  std::string old_;
};

const char kStl[] =
    "solid square\n"
    "facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 1 1 0\nendloop\nendfacet\n"
    "facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 1 0\nvertex 0 1 0\nendloop\nendfacet\n"
    "endsolid square\n";

const char kOff[] =
    "OFF\n5 2 0\n"
    "0 0 0\n1 0 0\n1 1 0\n0 1 0\n0.5 0.5 0\n"
    "4 0 1 2 3\n3 0 1 4\n";

// A flat n x n grid of squares as ASCII STL (2 n^2 facets), large enough to fill the pipe.
std::string grid_stl(int n) {
  std::ostringstream out;
  out << "solid grid\n";
  auto facet = [&](double ax, double ay, double bx, double by, double cx, double cy) {
    out << "facet normal 0 0 1\nouter loop\nvertex " << ax << " " << ay << " 0\nvertex " << bx
        << " " << by << " 0\nvertex " << cx << " " << cy << " 0\nendloop\nendfacet\n";
  };
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const double x0 = 0.01 * i, x1 = 0.01 * (i + 1), y0 = 0.01 * j, y1 = 0.01 * (j + 1);
      facet(x0, y0, x1, y0, x1, y1);
      facet(x0, y0, x1, y1, x0, y1);
    }
  }
  out << "endsolid grid\n";
  return out.str();
}

void expect_same(const MeshFileData& a, const MeshFileData& b) {
  EXPECT_EQ(a.mesh.uv_from_file, b.mesh.uv_from_file);
  EXPECT_EQ(a.mesh.positions, b.mesh.positions);
  EXPECT_EQ(a.mesh.rest_uv, b.mesh.rest_uv);
  EXPECT_EQ(a.mesh.triangles, b.mesh.triangles);
  EXPECT_EQ(a.triangle_places, b.triangle_places);
}

// True when this process has no child left (the reader was reaped).
bool no_children() {
  int status = 0;
  return waitpid(-1, &status, WNOHANG) < 0 && errno == ECHILD;
}

class meshIsolatedRead : public testing::Test {
 protected:
  test::TempDir dir_;
};

TEST_F(meshIsolatedRead, ValidFilesGiveTheInProcessResult) {
  for (const auto& [name, text] : {std::pair<std::string, std::string>{"square.stl", kStl},
                                   {"square.ply", kSquarePly},
                                   {"square.off", kOff},
                                   {"grid.stl", grid_stl(60)}}) {
    SCOPED_TRACE(name);
    const std::string path = dir_.write(name, text);
    const MeshFileData isolated = read_with_assimp(path);
    expect_same(isolated, read_with_assimp_in_process(path));
    EXPECT_FALSE(isolated.mesh.triangles.empty());
  }
  EXPECT_TRUE(no_children());
}

TEST_F(meshIsolatedRead, LargeResultCrossesThePipe) {
  const std::string path = dir_.write("grid.stl", grid_stl(60));
  const MeshFileData data = read_with_assimp(path);
  EXPECT_EQ(data.mesh.positions.size(), 61u * 61u);
  EXPECT_EQ(data.mesh.triangles.size(), 2u * 60u * 60u);
  EXPECT_EQ(data.triangle_places.size(), data.mesh.triangles.size());
  EXPECT_EQ(data.triangle_places.back(), "mesh 0, face 7199");
}

TEST_F(meshIsolatedRead, LoadMeshResultsAreUnchanged) {
  const TriMesh ply = load_mesh(dir_.write("square.ply", kSquarePly), 0.5);
  EXPECT_TRUE(ply.uv_from_file);
  ASSERT_EQ(ply.positions.size(), 4u);
  EXPECT_EQ(ply.positions[0], Vec3(0, 0, 0.5));
  EXPECT_EQ(ply.rest_uv[2], Vec2(1, 1));
  const TriMesh off = load_mesh(dir_.write("square.off", kOff), 1.0);
  EXPECT_EQ(off.positions.size(), 5u);
  EXPECT_EQ(off.triangles, (TriList{{0, 1, 2}, {0, 2, 3}, {0, 1, 4}}));
}

TEST_F(meshIsolatedRead, ReaderErrorsAreTheInProcessErrors) {
  // assimp's own error, and the PLY header check.
  for (const auto& [name, text] :
       {std::pair<std::string, std::string>{"noise.xyz", "this is no mesh\n"},
        {"open.ply", "ply\nformat ascii 1.0\nelement vertex 1\n"},
        {"broken.stl", "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0\n"}}) {
    SCOPED_TRACE(name);
    const std::string path = dir_.write(name, text);
    const std::string isolated = input_error_of([&] { read_with_assimp(path); });
    EXPECT_EQ(isolated, input_error_of([&] { read_with_assimp_in_process(path); }));
    EXPECT_EQ(isolated.rfind(path + ": ", 0), 0u) << isolated;
    EXPECT_EQ(isolated.find('\n'), std::string::npos) << isolated;
  }
  EXPECT_TRUE(no_children());
}

TEST_F(meshIsolatedRead, HangingReaderIsATimeout) {
  const ScopedEnv hook("TISSU_MESH_READ_TEST", "hang");
  const ScopedEnv limit("TISSU_MESH_READ_TIMEOUT", "0.5");
  const std::string path = dir_.write("square.ply", kSquarePly);
  const auto start = std::chrono::steady_clock::now();
  EXPECT_EQ(input_error_of([&] { load_mesh(path, 1.0); }),
            path + ": the mesh reader did not finish within 0.5 s (malformed file?)");
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_GE(seconds, 0.45);
  EXPECT_LT(seconds, 5.0);
  EXPECT_TRUE(no_children());
}

TEST_F(meshIsolatedRead, AbortingReaderIsACrash) {
  const ScopedEnv hook("TISSU_MESH_READ_TEST", "abort");
  const ScopedEnv limit("TISSU_MESH_READ_TIMEOUT", "5");
  const std::string path = dir_.write("square.stl", kStl);
  const auto start = std::chrono::steady_clock::now();
  testing::internal::CaptureStderr();
  const std::string error = input_error_of([&] { load_mesh(path, 1.0); });
  // The line the child prints before it aborts does not reach this process's stderr.
  EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
  EXPECT_EQ(error, path + ": the mesh reader crashed (signal 6: " + strsignal(SIGABRT) +
                       ") reading this file");
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 4.0);
  EXPECT_TRUE(no_children());
}

TEST_F(meshIsolatedRead, SegfaultingReaderIsACrash) {
  const ScopedEnv hook("TISSU_MESH_READ_TEST", "segv");
  const std::string path = dir_.write("square.off", kOff);
#if defined(__SANITIZE_ADDRESS__)
  // AddressSanitizer's own SEGV handler reports in the child and exits with status 1.
  const std::string expected = path + ": the mesh reader ended without a result (exit status 1)";
#else
  const std::string expected =
      path + ": the mesh reader crashed (signal 11: " + strsignal(SIGSEGV) + ") reading this file";
#endif
  EXPECT_EQ(input_error_of([&] { load_mesh(path, 1.0); }), expected);
  EXPECT_TRUE(no_children());
}

TEST_F(meshIsolatedRead, TheTestHookIsIgnoredForObjFiles) {
  // OBJ files are parsed in this process, without assimp.
  const ScopedEnv hook("TISSU_MESH_READ_TEST", "abort");
  const TriMesh mesh =
      load_mesh(dir_.write("square.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 3\n"), 1.0);
  EXPECT_EQ(mesh.triangles.size(), 1u);
}

TEST_F(meshIsolatedRead, TheChildDoesNotFlushTheParentsBuffers) {
  // Text buffered in this process before the read must come out once, not twice.
  const std::string log_path = dir_.file("log.txt");
  FILE* log = std::fopen(log_path.c_str(), "w");
  ASSERT_NE(log, nullptr);
  std::fputs("buffered\n", log);  // not flushed yet
  read_with_assimp(dir_.write("square.stl", kStl));
  {
    const ScopedEnv hook("TISSU_MESH_READ_TEST", "abort");
    input_error_of([&] { read_with_assimp(dir_.file("square.stl")); });
  }
  std::fclose(log);
  std::ifstream in(log_path);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(text, "buffered\n");
}

TEST_F(meshIsolatedRead, TimeLimitScalesWithFileSize) {
  unsetenv("TISSU_MESH_READ_TIMEOUT");
  EXPECT_EQ(mesh_read_timeout(0), 10.0);
  EXPECT_EQ(mesh_read_timeout(1), 11.0);
  EXPECT_EQ(mesh_read_timeout(1 << 20), 11.0);
  EXPECT_EQ(mesh_read_timeout((1 << 20) + 1), 12.0);
  EXPECT_EQ(mesh_read_timeout(100ull << 20), 110.0);
  {
    const ScopedEnv limit("TISSU_MESH_READ_TIMEOUT", "2.5");
    EXPECT_EQ(mesh_read_timeout(100ull << 20), 2.5);
  }
  for (const char* bad : {"", "0", "-1", "abc", "3s", "nan", "inf"}) {
    const ScopedEnv limit("TISSU_MESH_READ_TIMEOUT", bad);
    EXPECT_EQ(mesh_read_timeout(0), 10.0) << bad;
  }
}

}  // namespace
}  // namespace tissu
