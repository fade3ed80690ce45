#include "view/render_block.h"

#include <gtest/gtest.h>

#include "common/input_error_of.h"

namespace tissu {
namespace {

using test::input_error_of;

RenderSettings parse(const std::string& text) {
  const Json doc = Json::parse(text);
  JsonReader render(doc, "render");
  return parse_render_settings(render);
}

std::string parse_error(const std::string& text) {
  return input_error_of([&] { parse(text); });
}

TEST(render_settings, DefaultsWhenEmpty) {
  const RenderSettings s = parse("{}");
  EXPECT_EQ(s.width, 1280);
  EXPECT_EQ(s.height, 720);
  EXPECT_EQ(s.msaa, 4);
  EXPECT_EQ(s.fps, 30);
  EXPECT_EQ(s.slow_motion, 1.0);
  EXPECT_FALSE(s.camera.eye.has_value());
  EXPECT_FALSE(s.camera.target.has_value());
  EXPECT_EQ(s.lights.size(), 2u);
  EXPECT_EQ(s.cloth.pattern, ClothPattern::Weave);
  EXPECT_FALSE(s.ground.has_value());
  EXPECT_TRUE(s.caption.empty());
  EXPECT_FALSE(s.info);
}

TEST(render_settings, ReadsEveryKey) {
  const RenderSettings s = parse(R"({
    "width": 640, "height": 360, "msaa": 2, "fps": 60, "slow_motion": 4,
    "background": {"top": [0, 0, 0.5], "bottom": [1, 1, 1]},
    "camera": {"eye": [0, -3, 1], "target": [0, 0, 0.5], "up": [0, 0, 1], "fov": 30},
    "lights": [{"direction": [0, 1, -1], "color": [1, 0.9, 0.8], "intensity": 0.7}],
    "cloth": {"front_color": [1, 0, 0], "back_color": [0, 0, 1], "pattern": "checker",
              "pattern_size": 0.2, "wireframe": true, "wireframe_color": [0, 1, 0]},
    "ground": {"height": -1, "color": [0.3, 0.3, 0.3], "shadow": false},
    "caption": "Drape", "info": true})");
  EXPECT_EQ(s.width, 640);
  EXPECT_EQ(s.height, 360);
  EXPECT_EQ(s.msaa, 2);
  EXPECT_EQ(s.fps, 60);
  EXPECT_EQ(s.slow_motion, 4.0);
  EXPECT_EQ(s.background.top, Vec3(0, 0, 0.5));
  EXPECT_EQ(s.background.bottom, Vec3(1, 1, 1));
  ASSERT_TRUE(s.camera.fixed());
  EXPECT_EQ(*s.camera.eye, Vec3(0, -3, 1));
  EXPECT_EQ(*s.camera.target, Vec3(0, 0, 0.5));
  EXPECT_EQ(s.camera.fov_deg, 30.0);
  ASSERT_EQ(s.lights.size(), 1u);
  EXPECT_EQ(s.lights[0].direction, Vec3(0, 1, -1));
  EXPECT_EQ(s.lights[0].intensity, 0.7);
  EXPECT_EQ(s.cloth.front_color, Vec3(1, 0, 0));
  EXPECT_EQ(s.cloth.back_color, Vec3(0, 0, 1));
  EXPECT_EQ(s.cloth.pattern, ClothPattern::Checker);
  EXPECT_EQ(s.cloth.pattern_size, 0.2);
  EXPECT_TRUE(s.cloth.wireframe);
  EXPECT_EQ(s.cloth.wireframe_color, Vec3(0, 1, 0));
  ASSERT_TRUE(s.ground.has_value());
  EXPECT_EQ(s.ground->height, -1.0);
  EXPECT_FALSE(s.ground->shadow);
  EXPECT_EQ(s.caption, "Drape");
  EXPECT_TRUE(s.info);
}

TEST(render_settings, PlainBackgroundColourFillsBothEnds) {
  const RenderSettings s = parse(R"({"background": [0.1, 0.2, 0.3]})");
  EXPECT_EQ(s.background.top, Vec3(0.1, 0.2, 0.3));
  EXPECT_EQ(s.background.bottom, Vec3(0.1, 0.2, 0.3));
}

TEST(render_settings, PartialCameraLeavesTheRestAutomatic) {
  const RenderSettings s = parse(R"({"camera": {"fov": 25}})");
  EXPECT_FALSE(s.camera.fixed());
  EXPECT_EQ(s.camera.fov_deg, 25.0);
}

TEST(render_settings, UnknownKeyNamesPathAndSuggestion) {
  EXPECT_EQ(parse_error(R"({"widht": 640})"),
            "render.widht: unknown key (did you mean \"render.width\"?)");
  EXPECT_EQ(parse_error(R"({"cloth": {"patern": "weave"}})"),
            "render.cloth.patern: unknown key (did you mean \"render.cloth.pattern\"?)");
  EXPECT_EQ(parse_error(R"({"lights": [{"direction": [0, 0, -1], "colour": [1, 1, 1]}]})"),
            "render.lights[0].colour: unknown key (did you mean \"render.lights[0].color\"?)");
  EXPECT_EQ(parse_error(R"({"background": {"top": [0, 0, 0], "bottom": [1, 1, 1], "mid": [0, 0, 0]}})"),
            "render.background.mid: unknown key");
}

TEST(render_settings, RejectsOddAndOutOfRangeSizes) {
  EXPECT_EQ(parse_error(R"({"width": 641})"),
            "render.width: must be even (video encoders need even sizes), got 641");
  EXPECT_EQ(parse_error(R"({"height": 8})"), "render.height: must be in [16, 7680] pixels, got 8");
  EXPECT_EQ(parse_error(R"({"fps": 0})"), "render.fps: must be in [1, 240], got 0");
  EXPECT_EQ(parse_error(R"({"width": 640.5})"), "render.width: must be an integer, got 640.5");
}

TEST(render_settings, RejectsMsaaThree) {
  EXPECT_EQ(parse_error(R"({"msaa": 3})"), "render.msaa: must be 1, 2 or 4, got 3");
}

TEST(render_settings, FxaaIsSingleSampled) {
  EXPECT_EQ(parse(R"({"fxaa": true})").msaa, 1);
  EXPECT_TRUE(parse(R"({"fxaa": true, "msaa": 1})").fxaa);
  EXPECT_EQ(parse_error(R"({"fxaa": true, "msaa": 4})"),
            "render.fxaa: needs render.msaa 1 (FXAA replaces multisampling), got msaa 4");
}

TEST(render_settings, UpComesFromTheSceneUnlessGiven) {
  const Json none = Json::object();
  JsonReader empty(none, "render");
  const RenderSettings s = parse_render_settings(empty, Vec3(0, 2, 0));
  EXPECT_EQ(s.up, Vec3(0, 1, 0));
  EXPECT_EQ(s.camera.up, Vec3(0, 1, 0));
  // The default key light still comes from above: against the scene's up.
  EXPECT_LT(s.lights[0].direction.dot(Vec3(0, 1, 0)), 0.0);
  EXPECT_EQ(parse(R"({"up": [1, 0, 0]})").up, Vec3(1, 0, 0));
  EXPECT_EQ(up_from_gravity(Vec3(0, 0, -9.81)), Vec3(0, 0, 1));
  EXPECT_EQ(up_from_gravity(std::nullopt), Vec3(0, 0, 1));
  EXPECT_EQ(parse_error(R"({"up": [0, 0, 0]})"), "render.up: must not be the zero vector");
}

TEST(render_settings, RejectsBadValues) {
  EXPECT_EQ(parse_error(R"({"slow_motion": 0.5})"),
            "render.slow_motion: must be >= 1, got 0.5");
  EXPECT_EQ(parse_error(R"({"background": [0, 0, 2]})"),
            "render.background[2]: must be in [0, 1], got 2");
  EXPECT_EQ(parse_error(R"({"background": "blue"})"),
            "render.background: must be a colour [r, g, b] or a gradient {\"top\": [r, g, b], "
            "\"bottom\": [r, g, b]}");
  EXPECT_EQ(parse_error(R"({"cloth": {"pattern": "stripes"}})"),
            "render.cloth.pattern: unknown value \"stripes\"; expected one of weave, checker, none");
  EXPECT_EQ(parse_error(R"({"cloth": {"pattern_size": 0}})"),
            "render.cloth.pattern_size: must be > 0, got 0");
  EXPECT_EQ(parse_error(R"({"lights": [{"direction": [0, 0, 0]}]})"),
            "render.lights[0].direction: must not be the zero vector");
  EXPECT_EQ(parse_error(R"({"lights": [{}, {}, {}, {}, {}]})"),
            "render.lights: at most 4 lights, got 5");
  EXPECT_EQ(parse_error(R"({"camera": {"eye": [0, 0, 1], "target": [0, 0, 1]}})"),
            "render.camera.target: must differ from camera.eye");
  EXPECT_EQ(parse_error(R"({"camera": {"eye": [0, 0, 5], "target": [0, 0, 0]}})"),
            "render.camera.up: must not be parallel to the view direction");
  EXPECT_EQ(parse_error(R"({"camera": {"fov": 0}})").rfind("render.camera.fov: must be in (0, ", 0),
            0u);
  EXPECT_EQ(parse_error(R"({"info": "yes"})"), "render.info: must be true or false, got a string");
}

}  // namespace
}  // namespace tissu
