// Bad scene files, bad overrides and bad mesh files through `tissu run`: exit code 2, one
// line on stderr naming the file, the place and the problem, and nothing written. The
// parser's own messages are tested in tests/scene and tests/mesh; here the whole program.
#include "tissu_process.h"

namespace tissu::reliability {
namespace {

class BadInput : public TissuProcess {
 protected:
  // Runs `tissu run <scene> --out out --quiet [extra...]`.
  Outcome run_scene(const std::string& scene_path, std::vector<std::string> extra = {}) {
    std::vector<std::string> args{"run", scene_path, "--out", "out", "--quiet"};
    args.insert(args.end(), extra.begin(), extra.end());
    return run(args);
  }
  Outcome run_text(const std::string& text, std::vector<std::string> extra = {}) {
    return run_scene(write("scene.json", text), std::move(extra));
  }
  Outcome run_json(const Json& scene, std::vector<std::string> extra = {}) {
    return run_text(scene.dump(2), std::move(extra));
  }
  // The small scene with its cloth mesh read from `name` holding `text`.
  Outcome run_mesh(const std::string& name, const std::string& text) {
    if (!text.empty()) write(name, text);
    Json scene = small_scene();
    scene["cloth"]["mesh"] = {{"file", name}};
    return run_json(scene);
  }
};

// --- scene files ---

TEST_F(BadInput, SceneFileMissing) {
  EXPECT_BAD_INPUT(run_scene(path("absent.json")), path("absent.json"),
                   "cannot open scene file");
}

TEST_F(BadInput, SceneFileIsADirectory) {
  fs::create_directories(work_ / "dir.json");
  EXPECT_BAD_INPUT(run_scene(path("dir.json")), path("dir.json") +
                                                  ": cannot open scene file: is a directory");
}

TEST_F(BadInput, NotJson) {
  EXPECT_BAD_INPUT(run_text(std::string("\x7f" "ELF\x02\x01\x01", 7)), path("scene.json") + ":1:1:",
                   "not valid JSON");
}

TEST_F(BadInput, TruncatedFile) {
  const std::string text = small_scene().dump(2);
  EXPECT_BAD_INPUT(run_text(text.substr(0, text.size() / 2)), path("scene.json") + ":",
                   "not valid JSON", "unexpected end of input");
}

// "line:column" (1-based) of byte `at` in `text`.
std::string place_of(const std::string& text, size_t at) {
  const size_t line = std::count(text.begin(), text.begin() + at, '\n') + 1;
  const size_t line_start = text.rfind('\n', at == 0 ? 0 : at - 1);
  const size_t column = line_start == std::string::npos ? at + 1 : at - line_start;
  return std::to_string(line) + ":" + std::to_string(column);
}

TEST_F(BadInput, NaNAndInfinityAreNotJson) {
  std::string text = small_scene().dump(2);
  const size_t dt = text.find("0.0001");
  text.replace(dt, 6, "NaN");
  EXPECT_BAD_INPUT(run_text(text), path("scene.json") + ":" + place_of(text, dt) +
                                       ": not valid JSON",
                   "(NaN and Infinity are not JSON numbers: give a finite number)");
  text = small_scene().dump();
  const size_t g = text.find("-9.81");
  text.replace(g, 5, "-Infinity");
  EXPECT_BAD_INPUT(run_text(text), path("scene.json") + ":1:", "not valid JSON",
                   "(NaN and Infinity are not JSON numbers: give a finite number)");
}

TEST_F(BadInput, NumberTooLargeForADouble) {
  std::string text = small_scene().dump(2);
  const size_t dt = text.find("0.0001");
  text.replace(dt, 6, "1e999");
  EXPECT_BAD_INPUT(run_text(text), path("scene.json") + ":" + place_of(text, dt + 4) +
                                       ": not valid JSON: number overflow parsing '1e999'");
}

TEST_F(BadInput, WrongType) {
  Json scene = small_scene();
  scene["cloth"]["mesh"]["triangles"] = "many";
  EXPECT_BAD_INPUT(run_json(scene), path("scene.json") +
                                        ": cloth.mesh.triangles: must be a number, got a string");
}

TEST_F(BadInput, UnknownKeySuggestsTheClosest) {
  Json scene = small_scene();
  scene["cloth"]["materail"] = "silk";
  EXPECT_BAD_INPUT(run_json(scene), path("scene.json") + ": cloth.materail: unknown key "
                                                         "(did you mean \"cloth.material\"?)");
}

TEST_F(BadInput, MissingRequiredKey) {
  Json scene = small_scene();
  scene.erase("dt");
  EXPECT_BAD_INPUT(run_json(scene), path("scene.json") + ": dt: is required");
}

TEST_F(BadInput, ZeroSizeMesh) {
  Json scene = small_scene();
  scene["cloth"]["mesh"]["size"] = {0.4, 0};
  EXPECT_BAD_INPUT(run_json(scene), path("scene.json") + ": cloth.mesh.size[1]: must be in [1e-06, 1000000], got 0");
}

TEST_F(BadInput, TriangleCountThatWouldNotFitInMemory) {
  Json scene = small_scene();
  scene["cloth"]["mesh"]["triangles"] = 5e9;
  EXPECT_BAD_INPUT(run_json(scene), path("scene.json") +
                                        ": cloth.mesh.triangles: must be in [2, 4000000], got 5000000000");
}

TEST_F(BadInput, AbsurdSizesAndTransforms) {
  Json scene = small_scene();
  scene["cloth"]["mesh"]["size"] = {1e-9, 1};
  EXPECT_BAD_INPUT(run_json(scene), path("scene.json") +
                                        ": cloth.mesh.size[0]: must be in [1e-06, 1000000], got 1e-09");
  scene["cloth"]["mesh"]["size"] = {1e-3, 10};
  EXPECT_BAD_INPUT(run_json(scene), path("scene.json") +
                                        ": cloth.mesh.size: aspect ratio 10000 needs "
                                        "cloth.mesh.triangles >= 10000, got 100");
  scene = small_scene();
  scene["cloth"]["transform"] = {{"scale", 1e300}};
  scene["cloth"]["crumple"] = {{"amplitude", 1e300}};
  EXPECT_BAD_INPUT(run_json(scene), path("scene.json") +
                                        ": cloth.transform: moves vertex 0 to a non-finite position");
  scene = small_scene();
  scene["cloth"]["transform"] = {{"translate", {1.7e308, 0, 0}}};
  EXPECT_BAD_INPUT(run_json(scene), path("scene.json") +
                                        ": cloth.transform.translate[0]: must be <= 1e+300, got 1.7e+308");
}

TEST_F(BadInput, TooFewTrianglesForAGenerator) {
  Json scene = small_scene();
  scene["cloth"]["mesh"] = {{"generate", "disk"}, {"radius", 0.3}, {"triangles", 3}};
  EXPECT_BAD_INPUT(run_json(scene), path("scene.json") + ": cloth.mesh: ",
                   "triangles must be between 6 and");
}

TEST_F(BadInput, UnknownPresetAndIntegrator) {
  Json scene = small_scene();
  scene["cloth"]["material"] = "sílk";
  EXPECT_BAD_INPUT(run_json(scene), path("scene.json") + ": cloth.material: unknown preset",
                   "did you mean \"silk\"?");
  scene = small_scene();
  scene["integrator"] = "runge_kutta";
  EXPECT_BAD_INPUT(run_json(scene), path("scene.json") + ": integrator: unknown value",
                   "symplectic_euler");
}

TEST_F(BadInput, PinsThatSelectNoVertex) {
  Json scene = small_scene();
  scene["cloth"]["pins"] = Json::parse(R"([{"box": {"min": [5, 5, 5], "max": [6, 6, 6]}}])");
  EXPECT_BAD_INPUT(run_json(scene), path("scene.json") + ": cloth.pins[0].box: selects no vertex");
  scene["cloth"]["pins"] = Json::parse(R"([{"vertices": [3, 70000]}])");
  EXPECT_BAD_INPUT(run_json(scene), path("scene.json") + ": cloth.pins[0].vertices[1]: vertex "
                                                         "70000 out of range");
}

TEST_F(BadInput, ObstaclesWithZeroOrNegativeSize) {
  Json scene = small_scene();
  scene["obstacles"] = Json::parse(R"([{"sphere": {"center": [0, 0, 0], "radius": 0}}])");
  EXPECT_BAD_INPUT(run_json(scene), path("scene.json") + ": obstacles[0].sphere.radius: must be > 0");
  scene["obstacles"] = Json::parse(
      R"([{"cylinder": {"center": [0, 0, 0], "axis": [0, 1, 0], "radius": 0.1, "length": -2}}])");
  EXPECT_BAD_INPUT(run_json(scene), path("scene.json") + ": obstacles[0].cylinder.length: must be > 0");
  scene["obstacles"] = Json::parse(R"([{"plane": {"point": [0, 0, 0], "normal": [0, 0, 0]}}])");
  EXPECT_BAD_INPUT(run_json(scene), path("scene.json") +
                                        ": obstacles[0].plane.normal: must not be the zero vector");
}

// A cloth that starts inside an obstacle is named with the obstacle, the deepest vertex and
// its depth; before, the first step threw it out and the run was reported as diverged. A
// cloth laid exactly on a surface starts outside it.
TEST_F(BadInput, ClothStartsInsideAnObstacle) {
  Json scene = small_scene();
  scene["obstacles"] = Json::parse(R"([{"plane": {"point": [0, 0, 0], "normal": [0, 0, 1]}},
                                        {"sphere": {"center": [0, 0, 0.05], "radius": 0.1}}])");
  EXPECT_BAD_INPUT(run_json(scene), path("scene.json") + ": obstacles[1].sphere: cloth vertex ",
                   " starts 0.05 m inside it");
  scene["obstacles"].erase(1);
  const Outcome on_plane = run_json(scene);
  EXPECT_EQ(on_plane.exit_code, 0) << on_plane.err;
}

TEST_F(BadInput, SetPathThatDoesNotExist) {
  const std::string scene = write("scene.json", small_scene().dump());
  EXPECT_BAD_INPUT(run_scene(scene, {"--set", "cloth.mesh.trianglez=4"}),
                   "--set cloth.mesh.trianglez=4: cloth.mesh.trianglez: unknown key (did you mean "
                   "\"cloth.mesh.triangles\"?)");
  EXPECT_BAD_INPUT(run_scene(scene, {"--set", "name.first=x"}),
                   "--set name.first=x: name.first is inside a value that is not an object");
  Json with_obstacle = small_scene();
  with_obstacle["obstacles"] = Json::parse(R"([{"sphere": {"center": [0, 0, 0], "radius": 1}}])");
  const std::string other = write("other.json", with_obstacle.dump());
  EXPECT_BAD_INPUT(run_scene(other, {"--set", "obstacles.1.sphere.radius=2"}),
                   "--set obstacles.1.sphere.radius=2: obstacles.1 is not an element of an array of 1");
  EXPECT_BAD_INPUT(run_scene(other, {"--set", "obstacles.99999999999999999999.sphere.radius=2"}),
                   "--set obstacles.99999999999999999999.sphere.radius=2: obstacles.99999999999999999999"
                   " is not an element of an array of 1");
  EXPECT_BAD_INPUT(run_scene(scene, {"--set", "dt=1e999"}),
                   "--set dt=1e999: 1e999 is out of the range of a double");
}

// --- meshes named by a scene: the message names the scene, the key and the mesh file ---

TEST_F(BadInput, MeshFileMissing) {
  EXPECT_BAD_INPUT(run_mesh("", ""), path("scene.json") + ": cloth.mesh.file: must not be empty");
  EXPECT_BAD_INPUT(run_mesh("absent.obj", ""),
                   path("scene.json") + ": cloth.mesh.file: " + path("absent.obj") +
                       ": cannot open: No such file or directory");
}

TEST_F(BadInput, MeshFileIsNotARegularFile) {
  fs::create_directories(work_ / "dir.obj");
  EXPECT_BAD_INPUT(run_mesh("dir.obj", ""), path("scene.json") + ": cloth.mesh.file: " +
                                                path("dir.obj") + ": cannot open: not a regular file");
}

TEST_F(BadInput, MeshFileUnreadable) {
  if (geteuid() == 0) GTEST_SKIP() << "root reads files whatever their permissions";
  write("locked.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  fs::permissions(work_ / "locked.obj", fs::perms::none);
  EXPECT_BAD_INPUT(run_mesh("locked.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"),
                   path("scene.json") + ": cloth.mesh.file: " + path("locked.obj") +
                       ": cannot open: Permission denied");
}

TEST_F(BadInput, MeshFormatAssimpCannotRead) {
  EXPECT_BAD_INPUT(run_mesh("cloth.xyz", "this is no mesh\n"),
                   path("scene.json") + ": cloth.mesh.file: " + path("cloth.xyz") +
                       ": cannot read this format or file");
  EXPECT_BAD_INPUT(run_mesh("cloth.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n"),
                   path("scene.json") + ": cloth.mesh.file: " + path("cloth.off") +
                       ": cannot read this format or file");
}

// assimp runs in a child process with a time limit: a reader that hangs is killed, one that
// crashes is reported, both as one line, exit 2, nothing written. The child-only hook
// TISSU_MESH_READ_TEST makes the reader hang or abort on a valid file.
TEST_F(BadInput, MeshReaderThatHangsOrCrashesIsStoppedWithOneLine) {
  const std::string ply =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
      "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  const std::string where =
      path("scene.json") + ": cloth.mesh.file: " + path("cloth.ply") + ": the mesh reader ";
  setenv("TISSU_MESH_READ_TIMEOUT", "1", 1);
  setenv("TISSU_MESH_READ_TEST", "hang", 1);
  EXPECT_BAD_INPUT(run_mesh("cloth.ply", ply), where + "did not finish within 1 s");
  setenv("TISSU_MESH_READ_TEST", "abort", 1);
  EXPECT_BAD_INPUT(run_mesh("cloth.ply", ply), where + "crashed (signal 6");
  unsetenv("TISSU_MESH_READ_TEST");
  unsetenv("TISSU_MESH_READ_TIMEOUT");
  // The same file without the hook loads and runs.
  const Outcome ok = run_mesh("cloth.ply", ply);
  EXPECT_EQ(ok.exit_code, 0) << ok.err;
}

TEST_F(BadInput, MeshWithoutTriangles) {
  EXPECT_BAD_INPUT(run_mesh("cloth.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n"),
                   path("scene.json") + ": cloth.mesh.file: " + path("cloth.obj") +
                       ": contains no triangles");
}

TEST_F(BadInput, MeshIndexOutOfRange) {
  EXPECT_BAD_INPUT(run_mesh("cloth.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 3 40\n"),
                   path("scene.json") + ": cloth.mesh.file: " + path("cloth.obj") +
                       ": line 5 (face 2): vertex index 40 out of range (file has 3 vertices)");
  EXPECT_BAD_INPUT(
      run_mesh("cloth.ply",
               "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
               "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
               "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 9\n"),
      path("scene.json") + ": cloth.mesh.file: " + path("cloth.ply") + ": cannot read this ",
      "mFaces[0]::mIndices[2] is out of range");
}

TEST_F(BadInput, MeshZeroAreaTriangles) {
  EXPECT_BAD_INPUT(run_mesh("cloth.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nf 1 2 4\nf 1 2 3\n"),
                   path("scene.json") + ": cloth.mesh.file: " + path("cloth.obj") +
                       ": line 6 (face 2): zero area in 3D");
  EXPECT_BAD_INPUT(run_mesh("cloth.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 2\n"),
                   path("scene.json") + ": cloth.mesh.file: " + path("cloth.obj") +
                       ": line 5 (face 2): uses a vertex twice");
}

TEST_F(BadInput, MeshNonFiniteCoordinates) {
  EXPECT_BAD_INPUT(run_mesh("cloth.obj", "v 0 0 0\nv inf 0 0\nv 0 1 0\nf 1 2 3\n"),
                   path("scene.json") + ": cloth.mesh.file: " + path("cloth.obj") +
                       ": line 2: non-finite coordinate 'inf'");
  EXPECT_BAD_INPUT(
      run_mesh("cloth.stl",
               "solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex nan 0 0\n"
               "vertex 0 1 0\nendloop\nendfacet\nendsolid s\n"),
      path("scene.json") + ": cloth.mesh.file: " + path("cloth.stl") + ": mesh 0, face 0: ",
      "non-finite position");
}

TEST_F(BadInput, MeshMissingOrDegenerateTextureCoordinates) {
  // Curved and without texture coordinates: no rest shape.
  EXPECT_BAD_INPUT(run_mesh("cloth.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0.2\nv 0 1 0\nf 1 2 3\nf 1 3 4\n"),
                   path("scene.json") + ": cloth.mesh.file: " + path("cloth.obj") +
                       ": no texture coordinates and not flat: vertex id 2");
  // Texture coordinates on a line.
  EXPECT_BAD_INPUT(run_mesh("cloth.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 1\nvt 2 2\n"
                                         "f 1/1 2/2 3/3\n"),
                   path("scene.json") + ": cloth.mesh.file: " + path("cloth.obj") +
                       ": line 7 (face 1): zero area in (u, v)");
  // Some corners with and some without.
  EXPECT_BAD_INPUT(run_mesh("cloth.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvt 0 0\nvt 1 0\n"
                                         "vt 0 1\nf 1/1 2/2 3/3\nf 2 4 3\n"),
                   path("scene.json") + ": cloth.mesh.file: " + path("cloth.obj") +
                       ": line 9 (face 2): a corner has no texture coordinate index");
}

// Duplicate triangles are repaired, not rejected: one warning naming the mesh, and the run
// goes on.
TEST_F(BadInput, DuplicateTrianglesAreDroppedWithOneWarning) {
  const Outcome o = run_mesh("cloth.obj", "v 0 0 0\nv 0.1 0 0\nv 0.1 0.1 0\nv 0 0.1 0\n"
                                          "f 1 2 3\nf 1 3 4\nf 2 3 1\n");
  EXPECT_EQ(o.exit_code, 0) << o.err;
  EXPECT_EQ(o.err, "warning: " + path("cloth.obj") +
                       ": dropped 1 duplicate triangle (first: line 7 (face 3) repeats line 5 "
                       "(face 1))\n");
  EXPECT_TRUE(fs::exists(work_ / "out" / "report.json"));
}

}  // namespace
}  // namespace tissu::reliability
