#include "scene/json_reader.h"

#include <gtest/gtest.h>

#include "common/input_error_of.h"

namespace tissu {
namespace {

using test::input_error_of;

TEST(JsonReader, NamesPathAndRangeOfABadNumber) {
  const Json doc = Json::parse(R"({"material": {"density": -1}})");
  JsonReader root(doc, "cloth");
  JsonReader material = root.object("material");
  EXPECT_EQ(input_error_of([&] { material.number("density", Range::positive()); }),
            "cloth.material.density: must be > 0, got -1");
}

TEST(JsonReader, RejectsWrongTypes) {
  const Json doc = Json::parse(R"({"dt": "fast", "pos": [1, 2]})");
  JsonReader r(doc, "");
  EXPECT_EQ(input_error_of([&] { r.number("dt"); }), "dt: must be a number, got a string");
  EXPECT_EQ(input_error_of([&] { r.vec3("pos"); }), "pos: must be an array of 3 numbers, got an array of 2");
}

TEST(JsonReader, UnknownKeySuggestsClosest) {
  const Json doc = Json::parse(R"({"gravty": [0, 0, -9.81]})");
  JsonReader r(doc, "");
  r.vec3("gravity", Vec3::Zero());
  EXPECT_EQ(input_error_of([&] { r.finish(); }), "gravty: unknown key (did you mean \"gravity\"?)");
}

TEST(JsonReader, UnknownChoiceListsValidOnes) {
  const Json doc = Json::parse(R"({"integrator": "explicit_eulr"})");
  JsonReader r(doc, "");
  EXPECT_EQ(input_error_of([&] { r.choice("integrator", {"explicit_euler", "symplectic_euler"}); }),
            "integrator: unknown value \"explicit_eulr\" (did you mean \"explicit_euler\"?); "
            "expected one of explicit_euler, symplectic_euler");
}

TEST(JsonReader, IntegersMustBeWhole) {
  const Json doc = Json::parse(R"({"steps": 2.5, "n": 3})");
  JsonReader r(doc, "");
  EXPECT_EQ(input_error_of([&] { r.integer("steps"); }), "steps: must be an integer, got 2.5");
  EXPECT_EQ(r.integer("n", 0), 3);
  EXPECT_EQ(r.integer("absent", 7), 7);
}

TEST(JsonReader, RequiredKeyMissing) {
  const Json doc = Json::parse(R"({})");
  JsonReader r(doc, "cloth");
  EXPECT_EQ(input_error_of([&] { r.object("mesh"); }), "cloth.mesh: is required");
}

}  // namespace
}  // namespace tissu
