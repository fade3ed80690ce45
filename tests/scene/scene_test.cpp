// Scene validation: one test per class of bad input, each checking the message names the
// JSON path and the problem. And the parts of a valid scene that are built.
#include "scene/scene.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <functional>

#include "physics/materials.h"

namespace tissu {
namespace {

const char* kValid = R"({
  "name": "t", "dt": 1e-4, "steps": 10, "integrator": "symplectic_euler",
  "cloth": {"mesh": {"generate": "rectangle", "size": [0.5, 0.4], "triangles": 200,
                     "irregular": true, "seed": 3},
            "material": "cotton"}
})";

Json valid() { return Json::parse(kValid); }

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

std::string parse_error(const Json& doc) {
  return error_of([&] { parse_scene(doc, ""); });
}

std::string build_error(const Json& doc) {
  return error_of([&] { build_simulation(parse_scene(doc, "")); });
}

TEST(SceneValidation, ValidSceneParsesAndBuilds) {
  const Scene s = parse_scene(valid(), "");
  EXPECT_EQ(s.name, "t");
  EXPECT_EQ(s.steps, 10);
  EXPECT_FALSE(s.gravity.has_value()) << "no gravity key, no gravity";
  EXPECT_FALSE(s.air_damping.has_value());
  EXPECT_FALSE(s.wind.has_value());
  EXPECT_FALSE(s.position_correction.has_value());
  const Simulation sim = build_simulation(s);
  EXPECT_NEAR(sim.model.num_triangles(), 200, 20);
  double area = 0.0;
  for (const TriangleRest& r : sim.model.rest) area += r.area;
  EXPECT_NEAR(area, 0.2, 1e-12);
}

TEST(SceneValidation, OutOfRangeValueNamesPath) {
  Json doc = valid();
  doc["cloth"]["material"] = {{"density", -1},
                              {"stiffness", {{"weft", 100}, {"warp", 100}, {"shear", 10}}}};
  EXPECT_EQ(parse_error(doc), "cloth.material.density: must be > 0, got -1");
}

TEST(SceneValidation, WrongType) {
  Json doc = valid();
  doc["dt"] = "small";
  EXPECT_EQ(parse_error(doc), "dt: must be a number, got a string");
}

TEST(SceneValidation, NonPositiveTimeStep) {
  Json doc = valid();
  doc["dt"] = 0;
  EXPECT_EQ(parse_error(doc), "dt: must be in (0, 1], got 0");
}

TEST(SceneValidation, UnknownKeySuggestsClosest) {
  Json doc = valid();
  doc["gravty"] = {0, 0, -9.81};
  EXPECT_EQ(parse_error(doc), "gravty: unknown key (did you mean \"gravity\"?)");
  doc = valid();
  doc["cloth"]["mesh"]["triangels"] = 5;
  doc["cloth"]["mesh"].erase("triangles");
  EXPECT_EQ(parse_error(doc), "cloth.mesh.triangles: is required");
}

TEST(SceneValidation, MissingRequiredKey) {
  Json doc = valid();
  doc["cloth"].erase("mesh");
  EXPECT_EQ(parse_error(doc), "cloth.mesh: is required");
}

TEST(SceneValidation, UnknownPresetAndIntegrator) {
  Json doc = valid();
  doc["cloth"]["material"] = "coton";
  EXPECT_EQ(parse_error(doc),
            "cloth.material: unknown preset \"coton\" (did you mean \"cotton\"?); expected one "
            "of cotton, linen, silk, or an object");
  doc = valid();
  doc["integrator"] = "rk4";
  EXPECT_EQ(parse_error(doc).substr(0, 34), "integrator: unknown value \"rk4\"; e");
}

// The implicit solve's contact model: the constraints by default, the barrier on request.
TEST(SceneValidation, ImplicitContactModel) {
  Json doc = valid();
  EXPECT_EQ(parse_scene(doc, "").implicit.contact, ContactModel::Constraints);
  doc["implicit"] = Json::parse(R"({"contact": "barrier"})");
  EXPECT_EQ(parse_scene(doc, "").implicit.contact, ContactModel::Barrier);
  doc["implicit"] = Json::parse(R"({"contact": "penalty"})");
  EXPECT_EQ(parse_error(doc),
            "implicit.contact: unknown value \"penalty\"; expected one of constraints, barrier");
}

// The linear solver: the sparse Cholesky preconditioner by default, each other by its name.
TEST(SceneValidation, ImplicitLinearSolver) {
  Json doc = valid();
  EXPECT_EQ(parse_scene(doc, "").implicit.linear_solver, LinearSolver::Cholesky);
  const std::pair<const char*, LinearSolver> names[] = {
      {"cholesky", LinearSolver::Cholesky},
      {"block_jacobi_pcg", LinearSolver::BlockJacobiPcg},
      {"scalar_cholesky", LinearSolver::ScalarCholesky},
      {"scaled_scalar_cholesky", LinearSolver::ScaledScalarCholesky}};
  for (const auto& [name, solver] : names) {
    doc["implicit"]["linear_solver"] = name;
    EXPECT_EQ(parse_scene(doc, "").implicit.linear_solver, solver) << name;
  }
  doc["implicit"]["linear_solver"] = "choleski";
  EXPECT_EQ(parse_error(doc),
            "implicit.linear_solver: unknown value \"choleski\" (did you mean \"cholesky\"?); "
            "expected one of cholesky, block_jacobi_pcg, scalar_cholesky, scaled_scalar_cholesky");
}

// The barrier's activation distance: unset (0, the quarter edge) by default, in m when given.
TEST(SceneValidation, ImplicitBarrierDistance) {
  Json doc = valid();
  EXPECT_EQ(parse_scene(doc, "").implicit.barrier_distance, 0.0);
  doc["implicit"] = Json::parse(R"({"contact": "barrier", "barrier_distance": 0.002})");
  EXPECT_EQ(parse_scene(doc, "").implicit.barrier_distance, 0.002);
  doc["implicit"] = Json::parse(R"({"barrier_distance": 0})");
  EXPECT_EQ(parse_error(doc), "implicit.barrier_distance: must be > 0, got 0");
  doc["implicit"] = Json::parse(R"({"barrier_stiffness_dt": 0.004})");
  EXPECT_EQ(parse_scene(doc, "").implicit.barrier_stiffness_dt, 0.004);
  doc["implicit"] = Json::parse(R"({"barrier_stiffness_dt": -1})");
  EXPECT_EQ(parse_error(doc), "implicit.barrier_stiffness_dt: must be > 0, got -1");
  // The normal damping: critical (1) by default, 0 turns it off, never negative.
  EXPECT_EQ(parse_scene(valid(), "").implicit.barrier_damping, 1.0);
  doc["implicit"] = Json::parse(R"({"barrier_damping": 0})");
  EXPECT_EQ(parse_scene(doc, "").implicit.barrier_damping, 0.0);
  doc["implicit"] = Json::parse(R"({"barrier_damping": -0.5})");
  EXPECT_EQ(parse_error(doc), "implicit.barrier_damping: must be >= 0, got -0.5");
}

TEST(SceneValidation, StepsAndDurationExclusive) {
  Json doc = valid();
  doc["duration"] = 1.0;
  EXPECT_EQ(parse_error(doc), "steps: give exactly one of \"steps\" or \"duration\"");
}

TEST(SceneValidation, AbsurdTriangleCount) {
  Json doc = valid();
  doc["cloth"]["mesh"]["triangles"] = 1e12;
  EXPECT_EQ(parse_error(doc), "cloth.mesh.triangles: must be in [2, 4000000], got 1000000000000");
}

TEST(SceneValidation, ObstacleWithNonPositiveSize) {
  Json doc = valid();
  doc["obstacles"] = Json::parse(R"([{"sphere": {"center": [0, 0, 0], "radius": 0}}])");
  EXPECT_EQ(parse_error(doc), "obstacles[0].sphere.radius: must be > 0, got 0");
  doc["obstacles"] = Json::parse(R"([{"cylinder": {"center": [0, 0, 0], "axis": [0, 0, 0],
                                                   "radius": 1, "length": 1}}])");
  EXPECT_EQ(parse_error(doc), "obstacles[0].cylinder.axis: must not be the zero vector");
  doc["obstacles"] = Json::parse(R"([{"cube": {}}])");
  EXPECT_EQ(parse_error(doc),
            "obstacles[0].cube: unknown obstacle; expected sphere, cylinder, plane or mesh");
}

// A key written beside the obstacle instead of inside it is named, and so is a second
// obstacle in one element.
TEST(SceneValidation, ObstacleKeyOutsideItsObject) {
  Json doc = valid();
  doc["obstacles"] = Json::parse(R"([{"sphere": {"center": [0, 0, 0], "radius": 1},
                                      "friction": 0.4}])");
  EXPECT_EQ(parse_error(doc),
            "obstacles[0].friction: belongs inside \"sphere\", as {\"sphere\": {..., "
            "\"friction\": ...}}");
  doc["obstacles"] = Json::parse(R"([{"plane": {"point": [0, 0, 0], "normal": [0, 0, 1]},
                                      "sphere": {"center": [0, 0, 0], "radius": 1}}])");
  EXPECT_EQ(parse_error(doc),
            "obstacles[0]: holds both \"plane\" and \"sphere\"; each element of "
            "\"obstacles\" is one obstacle");
  doc["obstacles"] = Json::parse(R"([{}])");
  EXPECT_EQ(parse_error(doc),
            "obstacles[0]: must hold exactly one of \"sphere\", \"cylinder\", \"plane\", "
            "\"mesh\"");
}

TEST(SceneValidation, NonFiniteValues) {
  Json doc = valid();
  doc["gravity"] = {0, 0, std::nan("")};  // from --set or a program; a file cannot hold NaN
  EXPECT_EQ(parse_error(doc), "gravity[2]: must be finite, got NaN");
  doc = valid();
  doc["air_damping"] = -INFINITY;
  EXPECT_EQ(parse_error(doc), "air_damping: must be finite, got -Infinity");
}

TEST(SceneValidation, PinsOutOfRangeOrSelectingNothing) {
  Json doc = valid();
  doc["cloth"]["pins"] = Json::parse(R"([{"vertices": [0, 100000]}])");
  const std::string e = build_error(doc);
  EXPECT_EQ(e.substr(0, 55), "cloth.pins[0].vertices[1]: vertex 100000 out of range (");
  doc["cloth"]["pins"] = Json::parse(R"([{"box": {"min": [5, 5, 5], "max": [6, 6, 6]}}])");
  EXPECT_EQ(build_error(doc), "cloth.pins[0].box: selects no vertex");
}

TEST(SceneValidation, MaterialPresetWithOverrides) {
  Json doc = valid();
  doc["cloth"]["material"] = {{"preset", "linen"}, {"bending", 2e-5}};
  const Material linen = *material_preset("linen");
  Material m = parse_scene(doc, "").material;
  EXPECT_EQ(m.bending, 2e-5);
  EXPECT_EQ(m.bending_warp, linen.bending_warp) << "only the named fields change";
  EXPECT_EQ(m.density, linen.density);
  EXPECT_EQ(m.weft, linen.weft);
  EXPECT_EQ(m.warp, linen.warp);
  EXPECT_EQ(m.shear, linen.shear);
  EXPECT_EQ(m.coupling, linen.coupling);
  EXPECT_EQ(m.damping, linen.damping);
  EXPECT_EQ(m.name, "linen, modified");
  doc["cloth"]["material"] = {{"preset", "linen"}, {"stiffness", {{"warp", 2 * linen.warp}}}};
  m = parse_scene(doc, "").material;
  EXPECT_EQ(m.warp, 2 * linen.warp);
  EXPECT_EQ(m.weft, linen.weft);
  doc["cloth"]["material"] = {{"preset", "linen"}, {"bendin", 2e-5}};
  EXPECT_EQ(parse_error(doc), "cloth.material.bendin: unknown key (did you mean "
                              "\"cloth.material.bending\"?)");
  doc["cloth"]["material"] = {{"preset", "lnen"}};
  EXPECT_EQ(parse_error(doc).rfind("cloth.material.preset: unknown preset \"lnen\" (did you "
                                   "mean \"linen\"?)", 0), 0u) << parse_error(doc);
  doc["cloth"]["material"] = {{"preset", "linen"}, {"density", -1}};
  EXPECT_EQ(parse_error(doc), "cloth.material.density: must be > 0, got -1");
}

// The biphasic membrane's compression ratio: 1 (linear) unless given, in (0, 1].
TEST(SceneValidation, MaterialCompressionRatio) {
  Json doc = valid();
  EXPECT_EQ(parse_scene(doc, "").material.compression_ratio, 1.0);
  doc["cloth"]["material"] = {{"preset", "cotton"}, {"compression_ratio", 0.1}};
  EXPECT_EQ(parse_scene(doc, "").material.compression_ratio, 0.1);
  doc["cloth"]["material"]["compression_ratio"] = 0.0;
  EXPECT_EQ(parse_error(doc), "cloth.material.compression_ratio: must be in (0, 1], got 0");
  doc["cloth"]["material"]["compression_ratio"] = 1.5;
  EXPECT_EQ(parse_error(doc), "cloth.material.compression_ratio: must be in (0, 1], got 1.5");
}

TEST(SceneValidation, NonPositiveDefiniteStiffness) {
  Json doc = valid();
  doc["cloth"]["material"] = Json::parse(
      R"({"density": 0.1, "stiffness": {"weft": 100, "warp": 100, "coupling": 150, "shear": 10}})");
  EXPECT_EQ(parse_error(doc).substr(0, 58),
            "cloth.material.stiffness.coupling: must satisfy coupling^2");
}

class SceneFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("tissu_scene_test_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::string write(const std::string& name, const std::string& text) {
    const std::string path = (dir_ / name).string();
    std::ofstream(path) << text;
    return path;
  }
  std::filesystem::path dir_;
};

TEST_F(SceneFiles, SyntaxErrorNamesLineAndColumn) {
  const std::string path = write("bad.json", "{\n  \"name\": \"x\",\n  \"dt\": ,\n}\n");
  const std::string e = error_of([&] { load_scene(path); });
  EXPECT_EQ(e.substr(0, path.size() + 20), path + ":3:9: not valid JSON");
}

// JSON parsers keep the last of a key given twice; a scene names it instead, with its place,
// since either value may be the one the user meant.
TEST_F(SceneFiles, KeyGivenTwiceIsNamedWithItsPlace) {
  std::string text = kValid;
  text.insert(text.find('{') + 1, "\"dt\": 0.5,");
  const std::string top = write("top.json", text);
  EXPECT_EQ(error_of([&] { load_scene(top); }),
            top + ": dt: given twice (each key of an object once)");
  const std::string nested = write(
      "nested.json", "{\"name\": \"x\", \"obstacles\": [{\"sphere\": {}}, "
                     "{\"plane\": {\"friction\": 0.1, \"point\": [0, 0, 0], \"friction\": 0.2}}]}");
  EXPECT_EQ(error_of([&] { load_scene(nested); }),
            nested + ": obstacles[1].plane.friction: given twice (each key of an object once)");
}

TEST_F(SceneFiles, TruncatedFile) {
  const std::string path = write("cut.json", std::string(kValid).substr(0, 80));
  EXPECT_NE(error_of([&] { load_scene(path); }).find(": not valid JSON"), std::string::npos);
}

TEST_F(SceneFiles, CommentsAreAllowed) {
  const std::string path = write("c.json", std::string("// a comment\n") + kValid);
  EXPECT_EQ(load_scene(path).name, "t");
}

TEST_F(SceneFiles, MissingFile) {
  EXPECT_EQ(error_of([&] { load_scene((dir_ / "nope.json").string()); }),
            (dir_ / "nope.json").string() + ": cannot open scene file");
}

TEST_F(SceneFiles, ValidationErrorsNameTheFile) {
  Json doc = valid();
  doc["dt"] = -1;
  const std::string path = write("neg.json", doc.dump());
  EXPECT_EQ(error_of([&] { load_scene(path); }), path + ": dt: must be in (0, 1], got -1");
}

TEST_F(SceneFiles, OverridesAreAppliedAndValidated) {
  const std::string path = write("ok.json", kValid);
  const Scene s = load_scene(path, {"integrator=explicit_euler", "cloth.material=silk",
                                    "dt=2e-5", "gravity=[0,0,-1]"});
  EXPECT_EQ(s.integrator, Integrator::ExplicitEuler);
  EXPECT_EQ(s.material.name, "silk");
  EXPECT_DOUBLE_EQ(s.dt, 2e-5);
  EXPECT_EQ(*s.gravity, Vec3(0, 0, -1));
  EXPECT_EQ(error_of([&] { load_scene(path, {"dt=-3"}); }),
            "--set dt=-3: dt: must be in (0, 1], got -3");
  EXPECT_EQ(error_of([&] { load_scene(path, {"cloth.mesh.trianglez=4"}); }),
            "--set cloth.mesh.trianglez=4: cloth.mesh.trianglez: unknown key (did you mean "
            "\"cloth.mesh.triangles\"?)");
  EXPECT_EQ(error_of([&] { load_scene(path, {"dt"}); }),
            "--set dt: expected KEY=VALUE, e.g. --set dt=1e-4");
  EXPECT_EQ(error_of([&] { load_scene(path, {"name.first=3"}); }),
            "--set name.first=3: name.first is inside a value that is not an object");
}

TEST_F(SceneFiles, OverrideOfAPresetFieldKeepsThePreset) {
  const std::string path = write("ok.json", kValid);  // "material": "cotton"
  const Material cotton = *material_preset("cotton");
  const Scene s = load_scene(path, {"cloth.material.density=0.2",
                                    "cloth.material.stiffness.shear=3"});
  EXPECT_EQ(s.material.density, 0.2);
  EXPECT_EQ(s.material.shear, 3);
  EXPECT_EQ(s.material.weft, cotton.weft);
  EXPECT_EQ(s.material.bending, cotton.bending);
  EXPECT_EQ(s.material.name, "cotton, modified");
  EXPECT_EQ(load_scene(path, {"cloth.material.preset=silk"}).material.name, "silk, modified");
  EXPECT_EQ(error_of([&] { load_scene(path, {"cloth.material.bendng=1"}); }),
            "--set cloth.material.bendng=1: cloth.material.bendng: unknown key (did you mean "
            "\"cloth.material.bending\"?)");
}

TEST_F(SceneFiles, OverrideOfStepsReplacesDurationAndBack) {
  Json doc = valid();
  doc.erase("steps");
  doc["duration"] = 0.5;
  const std::string with_duration = write("d.json", doc.dump());
  EXPECT_EQ(load_scene(with_duration).steps, 5000);
  EXPECT_EQ(load_scene(with_duration, {"steps=7"}).steps, 7);
  const std::string with_steps = write("s.json", kValid);
  EXPECT_EQ(load_scene(with_steps, {"duration=0.01"}).steps, 100);
  EXPECT_EQ(load_scene(with_steps, {"duration=0.01", "steps=3"}).steps, 3);
}

TEST_F(SceneFiles, PinsByVertexIdAreRefusedForWeldedFiles) {
  // STL stores a vertex per corner: the ids of the welded vertices are not the file's.
  write("square.stl",
        "solid square\n"
        "facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 1 1 0\nendloop\n"
        "endfacet\n"
        "facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 1 0\nvertex 0 1 0\nendloop\n"
        "endfacet\n"
        "endsolid square\n");
  Json doc = valid();
  doc["cloth"]["mesh"] = {{"file", "square.stl"}};
  doc["cloth"]["pins"] = Json::parse(R"([{"box": {"min": [0, 0, 0], "max": [1, 0, 0]}},
                                         {"vertices": [3]}])");
  const std::string path = write("stl.json", doc.dump());
  EXPECT_EQ(error_of([&] { build_simulation(load_scene(path)); }),
            path + ": cloth.pins[1].vertices: " + (dir_ / "square.stl").string() +
                " has no vertex list of its own (corners at the same position were welded, "
                "as for STL), so vertex ids are not the file's: pin by \"box\" instead, or "
                "use OBJ, PLY or OFF");
  doc["cloth"]["pins"] = Json::parse(R"([{"box": {"min": [0, 0, 0], "max": [1, 0, 0]}}])");
  const Simulation sim = build_simulation(load_scene(write("box.json", doc.dump())));
  EXPECT_EQ(std::count(sim.model.pinned.begin(), sim.model.pinned.end(), 1), 2);
}

TEST_F(SceneFiles, MeshFileRelativeToScene) {
  Json doc = valid();
  doc["cloth"]["mesh"] = {{"file", "meshes/missing.obj"}};
  const std::string path = write("m.json", doc.dump());
  const Scene s = load_scene(path);
  EXPECT_EQ(s.mesh.file, (dir_ / "meshes/missing.obj").string());
  EXPECT_NE(error_of([&] { build_simulation(s); }).find("missing.obj"), std::string::npos);
}

TEST(SceneValidation, SelfCollisionAndKeyframes) {
  Json doc = valid();
  doc["self_collision"] = Json::parse(R"({"thickness": 0.003, "friction": 0.2})");
  const Scene s = parse_scene(doc, "");
  ASSERT_TRUE(s.self_collision.has_value());
  EXPECT_DOUBLE_EQ(s.self_collision->thickness, 0.003);
  EXPECT_DOUBLE_EQ(s.self_collision->friction, 0.2);
  EXPECT_TRUE(build_simulation(s).model.self_collision.has_value());
  doc["self_collision"] = Json::parse(R"({"thickness": 0})");
  EXPECT_EQ(parse_error(doc), "self_collision.thickness: must be in (0, 1], got 0");
  doc.erase("self_collision");
  doc["obstacles"] = Json::parse(R"([{"sphere": {"center": [0, 0, 0], "radius": 1,
      "motion": {"keyframes": [{"time": 0}, {"time": 1, "translate": [1, 0, 0]}]}}}])");
  EXPECT_EQ(parse_scene(doc, "").obstacles[0].motion.keyframes.size(), 2u);
  doc["obstacles"][0]["sphere"]["motion"]["keyframes"][1]["time"] = 0;
  EXPECT_EQ(parse_error(doc), "obstacles[0].sphere.motion.keyframes[1].time: keyframe times must "
                              "increase, got 0 after 0");
  doc["obstacles"][0]["sphere"]["motion"]["keyframes"][1] =
      Json::parse(R"({"time": 2, "rotate": {"axis": [0, 0, 1], "degrees": 90}})");
  EXPECT_EQ(parse_error(doc), "obstacles[0].sphere.motion.keyframes[1].rotate: only mesh obstacles "
                              "turn; spheres, cylinders and planes translate");
}

// A tetrahedron as an OFF file, and variants that are not closed or not manifold.
const char kTetrahedron[] = "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n"
                            "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";

TEST_F(SceneFiles, MeshObstaclesAreReadPlacedAndChecked) {
  write("tet.off", kTetrahedron);
  write("open.off", "OFF\n4 3 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n");
  Json doc = valid();
  doc["obstacles"] = Json::parse(R"([{"mesh": {"file": "tet.off", "friction": 0.4,
      "thickness": 0.002, "transform": {"scale": 2, "translate": [0, 0, -3]}}}])");
  const std::string path = write("mesh.json", doc.dump());
  const Simulation sim = build_simulation(load_scene(path));
  const Obstacle& ob = sim.model.obstacles[0];
  ASSERT_EQ(ob.kind, ObstacleKind::Mesh);
  EXPECT_DOUBLE_EQ(ob.friction, 0.4);
  EXPECT_DOUBLE_EQ(ob.thickness, 0.002);
  EXPECT_TRUE(ob.center.isApprox(Vec3(1, 1, -2)));  // the centre of the placed bounds
  Vec3 n;
  EXPECT_NEAR(ob.signed_distance(Vec3(0.2, 0.2, -3.5), 0.0, &n), 0.5, 1e-12);
  EXPECT_TRUE(n.isApprox(Vec3(0, 0, -1)));

  doc["obstacles"][0]["mesh"]["file"] = "open.off";
  const std::string open = write("open.json", doc.dump());
  EXPECT_EQ(error_of([&] { build_simulation(load_scene(open)); }),
            open + ": obstacles[0].mesh.file: " + (dir_ / "open.off").string() +
                ": not closed: the edge between vertex ids 1 and 2 borders only mesh 0, face 0 "
                "(mesh obstacles must be closed surfaces)");
  doc["obstacles"][0]["mesh"]["file"] = "nowhere.off";
  const std::string missing = write("missing.json", doc.dump());
  EXPECT_EQ(error_of([&] { build_simulation(load_scene(missing)); }),
            missing + ": obstacles[0].mesh.file: " + (dir_ / "nowhere.off").string() +
                ": cannot open: No such file or directory");
}

}  // namespace
}  // namespace tissu
