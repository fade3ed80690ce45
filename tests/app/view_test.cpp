// What the default view shows, through the tissu binary: the scene's up (minus gravity,
// or render.up) for the camera, the ground and the lights, and an automatic camera that
// frames the whole run.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>

#include "common/tissu_shell.h"
#include "video/image.h"
#include "video/png_io.h"

namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

class View : public tissu::test::TempDirTest {
 protected:
  View() : TempDirTest("tissu_view") {}

  tissu::test::ShellResult run(const std::string& args) {
    return tissu::test::run_tissu_shell(args, dir_ / "stderr.txt");
  }

  // Renders `scene` with two stills (the middle and the last frame) into dir_/name.
  tissu::Image render_last_still(const std::string& name, const Json& scene,
                                 const std::string& more = "") {
    const fs::path file = dir_ / (name + ".json");
    std::ofstream(file) << scene.dump(2);
    const fs::path out = dir_ / name;
    const auto r = run("render " + file.string() + " --out " + out.string() +
                       " --no-mp4 --stills 1 --quiet " + more);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    for (const auto& entry : fs::directory_iterator(out / "stills")) {
      return tissu::read_png(entry.path().string());
    }
    ADD_FAILURE() << "no still in " << out;
    return {};
  }
};

// A sheet falling onto a sphere above a ground, with z up. Small frames keep it quick.
Json z_up_scene() {
  return Json::parse(R"({
    "name": "drop", "dt": 2e-4, "steps": 1500, "integrator": "symplectic_euler",
    "cloth": {"mesh": {"generate": "rectangle", "size": [0.6, 0.6], "triangles": 300,
                       "irregular": false},
              "material": "silk",
              "transform": {"translate": [0.05, 0.0, 0.45]}},
    "gravity": [0, 0, -9.81], "air_damping": 0.5,
    "obstacles": [{"sphere": {"center": [0, 0, 0.2], "radius": 0.2}},
                  {"plane": {"point": [0, 0, 0], "normal": [0, 0, 1]}}],
    "render": {"width": 320, "height": 240, "fps": 20, "ground": {"height": 0}}
  })");
}

// The same scene with y up: every position p of the z-up scene is at (p.x, p.z, -p.y).
Json y_up_scene() {
  Json s = z_up_scene();
  s["gravity"] = {0, -9.81, 0};
  s["cloth"]["transform"] = Json::parse(
      R"({"rotate": {"axis": [1, 0, 0], "degrees": -90}, "translate": [0.05, 0.45, 0.0]})");
  s["obstacles"][0]["sphere"]["center"] = {0, 0.2, 0};
  s["obstacles"][1]["plane"]["normal"] = {0, 1, 0};
  return s;
}

// Pixels of the cloth's front colour (red, render.cloth.front_color's default).
int cloth_pixels(const tissu::Image& image, int* on_border = nullptr) {
  int count = 0;
  if (on_border) *on_border = 0;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      const uint8_t* p = image.pixel(x, y);
      if (p[0] > 60 && p[0] > 2 * p[1] && p[0] > 2 * p[2]) {
        ++count;
        if (on_border && (x == 0 || y == 0 || x == image.width - 1 || y == image.height - 1)) {
          ++*on_border;
        }
      }
    }
  }
  return count;
}

void expect_same_picture(const tissu::Image& a, const tissu::Image& b) {
  ASSERT_EQ(a.width, b.width);
  const tissu::ImageDiff diff = tissu::compare_images(a, b);
  EXPECT_TRUE(tissu::FrameTolerance{}.accepts(diff))
      << "differing pixels " << diff.fraction_over_threshold << ", mean " << diff.mean_abs_diff
      << ", PSNR " << diff.psnr_db << " dB";
}

TEST_F(View, GravityAlongMinusYLooksLikeTheSameSceneWithZUp) {
  const tissu::Image z_up = render_last_still("z_up", z_up_scene());
  const tissu::Image y_up = render_last_still("y_up", y_up_scene());
  ASSERT_GT(cloth_pixels(z_up), 1000);  // the picture shows the cloth at all
  expect_same_picture(z_up, y_up);
}

TEST_F(View, RenderUpKeyTurnsTheViewWithoutGravity) {
  Json z = z_up_scene(), y = y_up_scene();
  z.erase("gravity");
  y.erase("gravity");
  z["steps"] = y["steps"] = 100;
  y["render"]["up"] = {0, 1, 0};
  const tissu::Image z_up = render_last_still("z_up", z);
  const tissu::Image y_up = render_last_still("y_up", y);
  ASSERT_GT(cloth_pixels(z_up), 1000);
  expect_same_picture(z_up, y_up);
  // Without the key the y-up scene is seen from the side: another picture.
  y["render"].erase("up");
  const tissu::ImageDiff diff = tissu::compare_images(z_up, render_last_still("y_side", y));
  EXPECT_FALSE(tissu::FrameTolerance{}.accepts(diff));
}

// A sheet thrown sideways without gravity: it leaves the place where it starts.
Json thrown_scene() {
  return Json::parse(R"({
    "name": "thrown", "dt": 1e-4, "steps": 10000, "integrator": "symplectic_euler",
    "cloth": {"mesh": {"generate": "rectangle", "size": [0.4, 0.4], "triangles": 200},
              "material": "silk", "velocity": [2.0, 0, 0.5]},
    "render": {"width": 320, "height": 240, "fps": 10}
  })");
}

TEST_F(View, AutomaticCameraFramesTheWholeRun) {
  int on_border = -1;
  const tissu::Image last = render_last_still("run", thrown_scene());
  const int pixels = cloth_pixels(last, &on_border);
  EXPECT_GT(pixels, 300);
  EXPECT_EQ(on_border, 0);
  // Framing the first frame only (the earlier behaviour), the sheet has left the picture.
  Json first = thrown_scene();
  first["render"]["camera"] = {{"framing", "first"}};
  EXPECT_LT(cloth_pixels(render_last_still("first", first)), pixels / 10);
}

TEST_F(View, UnknownFramingIsAOneLineError) {
  Json s = thrown_scene();
  s["render"]["camera"] = {{"framing", "all"}};
  const fs::path file = dir_ / "bad.json";
  std::ofstream(file) << s.dump(2);
  const auto r = run("render " + file.string() + " --out " + (dir_ / "out").string() + " --quiet");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("render.camera.framing"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "out"));
}

}  // namespace
