// A clamped, graded disk from a scene (docs/scenes.md): cloth.mesh's inner_radius and
// grading build the mesh generate_disk builds, each bad value is one line naming its key,
// and the "disk" pin region selects exactly the vertices within its radius.
#include <gtest/gtest.h>

#include <cmath>

#include "common/input_error_of.h"
#include "mesh/generate.h"
#include "scene/scene.h"

namespace tissu {
namespace {

// Cusick's set-up (tests/physics/cusick.h): a 0.15 m disk, a circle of vertices at
// 0.09 m, edges halved over 0.09-0.115 m with 0.015 m transitions; 1.5 mm above z = 0.3.
Json graded_scene() {
  return Json::parse(R"({
    "name": "t", "dt": 0.02, "steps": 1, "integrator": "backward_euler",
    "cloth": {"mesh": {"generate": "disk", "radius": 0.15, "triangles": 1500, "seed": 2,
                       "inner_radius": 0.09,
                       "grading": {"inner": 0.09, "outer": 0.115, "fine_ratio": 0.5,
                                   "transition": 0.015}},
              "transform": {"translate": [0, 0, 0.3]},
              "material": "cotton"}
  })");
}

std::string parse_error(const Json& doc) {
  return test::input_error_of([&] { parse_scene(doc, ""); });
}

std::string build_error(const Json& doc) {
  return test::input_error_of([&] { build_simulation(parse_scene(doc, "")); });
}

// Mean edge (m) of the triangles whose centroid lies at a distance in [lo, hi) from the centre.
double mean_edge(const Model& model, double lo, double hi) {
  double sum = 0.0;
  int count = 0;
  for (const Tri& t : model.triangles) {
    const Vec2 c = (model.rest_uv[t[0]] + model.rest_uv[t[1]] + model.rest_uv[t[2]]) / 3.0;
    if (c.norm() < lo || c.norm() >= hi) continue;
    for (int k = 0; k < 3; ++k) sum += (model.rest_uv[t[k]] - model.rest_uv[t[(k + 1) % 3]]).norm();
    count += 3;
  }
  return sum / count;
}

TEST(DiskScene, GradedDiskIsTheGeneratorsMesh) {
  const Simulation sim = build_simulation(parse_scene(graded_scene(), ""));
  const TriMesh expected =
      generate_disk(0.15, 1500, 2, 0.09, DiskGrading{0.09, 0.115, 0.5, 0.015});
  ASSERT_EQ(sim.model.rest_uv.size(), expected.rest_uv.size());
  EXPECT_EQ(sim.model.triangles, expected.triangles);
  int on_circle = 0;
  for (size_t i = 0; i < expected.rest_uv.size(); ++i) {
    EXPECT_EQ(sim.model.rest_uv[i], expected.rest_uv[i]);
    on_circle += std::abs(expected.rest_uv[i].norm() - 0.09) < 1e-12 ? 1 : 0;
  }
  EXPECT_GE(on_circle, 20) << "a circle of vertices at inner_radius";
  // The band's edges are about half those beyond the band and its transition.
  const double band = mean_edge(sim.model, 0.09, 0.115);
  const double outside = mean_edge(sim.model, 0.13, 1.0);
  EXPECT_LT(band, 0.7 * outside) << band << " m in the band, " << outside << " m outside";
}

TEST(DiskScene, InnerRadiusAloneGivesACircleOfVertices) {
  Json doc = graded_scene();
  doc["cloth"]["mesh"].erase("grading");
  doc["cloth"]["mesh"]["irregular"] = false;
  const Simulation sim = build_simulation(parse_scene(doc, ""));
  const TriMesh expected = generate_disk(0.15, 1500, false, 2, 0.09);
  EXPECT_EQ(sim.model.triangles, expected.triangles);
  int on_circle = 0;
  for (const Vec2& p : sim.model.rest_uv) on_circle += std::abs(p.norm() - 0.09) < 1e-12;
  EXPECT_GE(on_circle, 20);
}

TEST(DiskScene, EachBadKeyIsOneLineNamingIt) {
  struct Case {
    const char* key;  // in cloth.mesh, "grading." for the grading's
    Json value;
    const char* error;
  };
  const std::vector<Case> cases = {
      {"inner_radius", 0.0, "cloth.mesh.inner_radius: must be in (0, 0.15), got 0"},
      {"inner_radius", 0.15, "cloth.mesh.inner_radius: must be in (0, 0.15), got 0.15"},
      {"inner_radius", "a", "cloth.mesh.inner_radius: must be a number, got a string"},
      {"grading.inner", -0.01, "cloth.mesh.grading.inner: must be in [0, 0.15), got -0.01"},
      {"grading.outer", 0.05, "cloth.mesh.grading.outer: must be in (0.09, 0.15], got 0.05"},
      {"grading.outer", 0.2, "cloth.mesh.grading.outer: must be in (0.09, 0.15], got 0.2"},
      {"grading.fine_ratio", 0.0, "cloth.mesh.grading.fine_ratio: must be in (0, 1], got 0"},
      {"grading.fine_ratio", 1.5, "cloth.mesh.grading.fine_ratio: must be in (0, 1], got 1.5"},
      {"grading.transition", -1.0,
       "cloth.mesh.grading.transition: must be in [0, 0.15], got -1"},
      {"grading.fine_rato", 0.5,
       "cloth.mesh.grading.fine_rato: unknown key (did you mean \"cloth.mesh.grading.fine_ratio\"?)"},
      {"irregular", true, "cloth.mesh.irregular: unknown key"},
  };
  for (const Case& c : cases) {
    Json doc = graded_scene();
    Json& mesh = doc["cloth"]["mesh"];
    const std::string key = c.key;
    if (key.rfind("grading.", 0) == 0) {
      mesh["grading"][key.substr(8)] = c.value;
    } else {
      mesh[key] = c.value;
    }
    EXPECT_EQ(parse_error(doc), c.error) << key;
  }
  Json doc = graded_scene();
  doc["cloth"]["mesh"]["grading"].erase("fine_ratio");
  EXPECT_EQ(parse_error(doc), "cloth.mesh.grading.fine_ratio: is required");
  doc = graded_scene();
  doc["cloth"]["mesh"].erase("inner_radius");
  EXPECT_EQ(parse_error(doc), "cloth.mesh.grading: needs cloth.mesh.inner_radius (the graded "
                              "disk has a circle of vertices there)");
}

TEST(DiskScene, DiskKeysDoNotApplyToRectangles) {
  Json doc = graded_scene();
  doc["cloth"]["mesh"] = {{"generate", "rectangle"}, {"size", {0.3, 0.3}},
                          {"triangles", 200}, {"inner_radius", 0.09}};
  EXPECT_EQ(parse_error(doc), "cloth.mesh.inner_radius: unknown key");
  doc["cloth"]["mesh"].erase("inner_radius");
  doc["cloth"]["mesh"]["grading"] = graded_scene()["cloth"]["mesh"]["grading"];
  EXPECT_EQ(parse_error(doc), "cloth.mesh.grading: unknown key");
}

// Pinned: the vertices within 0.09 m of the centre, at z = 0.3 after the transform. The
// circle at inner_radius is pinned whole, so the triangles inside it are a clamp.
TEST(DiskScene, DiskPinsSelectExactlyTheVerticesInside) {
  Json doc = graded_scene();
  doc["cloth"]["pins"] = Json::parse(R"([{"disk": {"center": [0, 0, 0.3], "radius": 0.09}}])");
  const Simulation sim = build_simulation(parse_scene(doc, ""));
  int pinned = 0, inside = 0;
  for (size_t i = 0; i < sim.model.rest_uv.size(); ++i) {
    const double r = sim.model.rest_uv[i].norm();
    EXPECT_EQ(sim.model.pinned[i] != 0, r <= 0.09 + 1e-12) << "vertex " << i << " at r " << r;
    pinned += sim.model.pinned[i];
    inside += r <= 0.09 + 1e-12;
  }
  EXPECT_EQ(pinned, inside);
  EXPECT_GT(pinned, 100);
  // A ball in 3D: centred 0.05 m above the cloth with radius 0.1 m, it reaches the vertices
  // within sqrt(0.1^2 - 0.05^2) = 0.0866 m of the centre line.
  doc["cloth"]["pins"] = Json::parse(R"([{"disk": {"center": [0, 0, 0.35], "radius": 0.1}}])");
  const Simulation above = build_simulation(parse_scene(doc, ""));
  for (size_t i = 0; i < above.model.rest_uv.size(); ++i) {
    const double r = above.model.rest_uv[i].norm();
    if (std::abs(r - std::sqrt(0.0075)) < 1e-9) continue;  // on the edge: either way
    EXPECT_EQ(above.model.pinned[i] != 0, r < std::sqrt(0.0075)) << "vertex " << i;
  }
}

TEST(DiskScene, DiskPinErrors) {
  Json doc = graded_scene();
  doc["cloth"]["pins"] = Json::parse(R"([{"disk": {"center": [1, 1, 1], "radius": 0.05}}])");
  EXPECT_EQ(build_error(doc), "cloth.pins[0].disk: selects no vertex");
  doc["cloth"]["pins"] = Json::parse(R"([{"disk": {"center": [0, 0, 0.3], "radius": 0}}])");
  EXPECT_EQ(parse_error(doc), "cloth.pins[0].disk.radius: must be > 0, got 0");
  doc["cloth"]["pins"] = Json::parse(R"([{"disk": {"radius": 0.05}}])");
  EXPECT_EQ(parse_error(doc), "cloth.pins[0].disk.center: is required");
  doc["cloth"]["pins"] = Json::parse(R"([{"disc": {"radius": 0.05}}])");
  EXPECT_EQ(parse_error(doc), "cloth.pins[0]: needs \"vertices\", \"box\" or \"disk\"");
}

}  // namespace
}  // namespace tissu
