#include "render/renderer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "render/render_error.h"
#include "test_scenes.h"

namespace tissu {
namespace {

using test::pixel;
using test::Rgb;

std::vector<uint8_t> render(const RenderSettings& settings, const FrameContent& frame) {
  Renderer renderer(settings);
  renderer.draw(frame);
  std::vector<uint8_t> rgb;
  renderer.read_rgb(rgb);
  return rgb;
}

// Camera straight above the origin looking down, +y up on screen.
RenderSettings top_view(int width, int height, double eye_z) {
  RenderSettings s = test::plain_settings(width, height);
  s.camera.eye = Vec3(0, 0, eye_z);
  s.camera.target = Vec3::Zero();
  s.camera.up = Vec3::UnitY();
  s.camera.fov_deg = 60;
  return s;
}

// Pixel position of world point p for the camera of `s` (fixed camera only).
std::pair<int, int> project(const RenderSettings& s, const Vec3& p) {
  const Vec3 eye = *s.camera.eye;
  const Vec3 f = (*s.camera.target - eye).normalized();
  const Vec3 r = f.cross(s.camera.up).normalized();
  const Vec3 u = r.cross(f);
  const double t = std::tan(s.camera.fov_deg * M_PI / 360.0);
  const double aspect = static_cast<double>(s.width) / s.height;
  const double depth = (p - eye).dot(f);
  const double x = (p - eye).dot(r) / (depth * t * aspect), y = (p - eye).dot(u) / (depth * t);
  return {static_cast<int>((0.5 + 0.5 * x) * s.width), static_cast<int>((0.5 - 0.5 * y) * s.height)};
}

int brightness(const Rgb& c) { return c.r + c.g + c.b; }

TEST(render_frame, FrontAndBackSidesShowTheirColours) {
  RenderSettings s = top_view(64, 64, 3);
  s.cloth.front_color = Vec3(0.9, 0.1, 0.1);
  s.cloth.back_color = Vec3(0.1, 0.1, 0.9);
  s.lights = {Light{Vec3(0, 0, -1), Vec3::Ones(), 1.0}, Light{Vec3(0, 0, 1), Vec3::Ones(), 1.0}};
  const FrameContent cloth = test::flat_cloth(4, 2.0);  // counter-clockwise seen from +z

  const Rgb front = pixel(render(s, cloth), 64, 32, 32);
  EXPECT_GT(front.r, 200);
  EXPECT_LT(front.g, 110);
  EXPECT_LT(front.b, 110);

  s.camera.eye = Vec3(0, 0, -3);  // from below: the back side
  const Rgb back = pixel(render(s, cloth), 64, 32, 32);
  EXPECT_GT(back.b, 200);
  EXPECT_LT(back.r, 110);
  EXPECT_LT(back.g, 110);
}

TEST(render_frame, SphereCoversADiscOfItsProjectedRadius) {
  const int size = 200;
  RenderSettings s = top_view(size, size, 4);
  s.camera.fov_deg = 40;
  FrameContent frame;
  frame.obstacles.push_back(test::sphere(Vec3::Zero(), 0.5));
  const std::vector<uint8_t> rgb = render(s, frame);
  long count = 0;
  double sum_x = 0, sum_y = 0;
  for (int y = 0; y < size; ++y) {
    for (int x = 0; x < size; ++x) {
      if (brightness(pixel(rgb, size, x, y)) > 0) {
        ++count;
        sum_x += x + 0.5;
        sum_y += y + 0.5;
      }
    }
  }
  // A sphere seen from distance d fills a cone of half angle asin(r / d).
  const double expected = std::tan(std::asin(0.5 / 4.0)) / std::tan(20.0 * M_PI / 180.0) * size / 2;
  EXPECT_NEAR(std::sqrt(count / M_PI), expected, 0.01 * expected);
  EXPECT_NEAR(sum_x / count, size / 2.0, 0.5);
  EXPECT_NEAR(sum_y / count, size / 2.0, 0.5);
}

int covered_pixels(const std::vector<uint8_t>& rgb) {
  int n = 0;
  for (size_t i = 0; i < rgb.size(); i += 3) n += rgb[i] + rgb[i + 1] + rgb[i + 2] > 0;
  return n;
}

TEST(render_frame, CylinderAlongAnyAxisCoversItsProjectedRectangle) {
  // Seen from far above, a cylinder lying along (1, 1, 0) shows a 2h x 2r rectangle
  // (its caps are edge-on; perspective adds well under 1% from this far).
  const int size = 200;
  const double distance = 60;
  RenderSettings s = top_view(size, size, distance);
  s.camera.fov_deg = 3.5;
  FrameContent frame;
  ObstacleShape cylinder;
  cylinder.kind = ObstacleShape::Kind::Cylinder;
  cylinder.axis = Vec3(1, 1, 0);
  cylinder.radius = 0.2;
  cylinder.half_length = 0.8;
  frame.obstacles.push_back(cylinder);
  const double pixels_per_m = size / (2 * distance * std::tan(1.75 * M_PI / 180.0));
  const double expected = (2 * 0.8) * (2 * 0.2) * pixels_per_m * pixels_per_m;
  EXPECT_NEAR(covered_pixels(render(s, frame)), expected, 0.01 * expected);
}

TEST(render_frame, PlaneFillsTheViewFacingItAndVanishesEdgeOn) {
  RenderSettings s = top_view(64, 64, 3);
  FrameContent frame;
  ObstacleShape plane;
  plane.kind = ObstacleShape::Kind::Plane;
  plane.axis = Vec3(0, 0.2, 1);
  frame.obstacles.push_back(plane);
  EXPECT_EQ(covered_pixels(render(s, frame)), 64 * 64);
  frame.obstacles[0].axis = Vec3(1, 0, 0);  // contains the view direction
  EXPECT_LT(covered_pixels(render(s, frame)), 64 * 2);
}

TEST(render_frame, BackgroundGradientRunsFromTopToBottom) {
  RenderSettings s = test::plain_settings(64, 32);
  s.background.top = Vec3(1, 0, 0);
  s.background.bottom = Vec3(0, 0, 1);
  s.camera.eye = Vec3(0, -3, 0);
  s.camera.target = Vec3::Zero();
  const std::vector<uint8_t> rgb = render(s, FrameContent{});
  for (int x : {0, 31, 63}) {
    EXPECT_EQ(pixel(rgb, 64, x, 0).r, 255);
    EXPECT_EQ(pixel(rgb, 64, x, 0).b, 0);
    EXPECT_EQ(pixel(rgb, 64, x, 31).r, 0);
    EXPECT_EQ(pixel(rgb, 64, x, 31).b, 255);
  }
  // Row 15 from the top is 16 rows of 31 up from the bottom.
  EXPECT_NEAR(pixel(rgb, 64, 10, 15).r, 255.0 * 16 / 31, 1.0);
  EXPECT_NEAR(pixel(rgb, 64, 10, 15).b, 255.0 * 15 / 31, 1.0);
}

TEST(render_frame, MsaaSmoothsEdgesAndLeavesInteriorsAlone) {
  const int size = 96;
  RenderSettings s = top_view(size, size, 3);
  FrameContent cloth = test::flat_cloth(2, 1.6);
  for (Vec3& p : cloth.positions) p = Eigen::AngleAxisd(0.3, Vec3::UnitZ()) * p;  // slanted edges
  const std::vector<uint8_t> plain = render(s, cloth);
  s.msaa = 4;
  const std::vector<uint8_t> smooth = render(s, cloth);

  auto is_cloth = [&](int x, int y) { return brightness(pixel(plain, size, x, y)) > 0; };
  int interior = 0, changed = 0, changed_away_from_edges = 0, blended = 0;
  for (int y = 1; y < size - 1; ++y) {
    for (int x = 1; x < size - 1; ++x) {
      bool near_edge = false;
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) near_edge |= is_cloth(x + dx, y + dy) != is_cloth(x, y);
      }
      const Rgb a = pixel(plain, size, x, y), b = pixel(smooth, size, x, y);
      const bool differs = a.r != b.r || a.g != b.g || a.b != b.b;
      if (differs) ++changed;
      if (differs && !near_edge) ++changed_away_from_edges;
      if (!near_edge && is_cloth(x, y)) {
        ++interior;
        EXPECT_NEAR(a.r, b.r, 1);
        EXPECT_NEAR(a.g, b.g, 1);
        EXPECT_NEAR(a.b, b.b, 1);
      }
      // Partly covered pixels: neither background nor the full cloth colour.
      if (near_edge && b.r > 0 && b.r < a.r - 20 && is_cloth(x, y)) ++blended;
    }
  }
  EXPECT_GT(interior, 1000);
  EXPECT_GT(changed, 50);
  EXPECT_GT(blended, 20);
  EXPECT_EQ(changed_away_from_edges, 0);
}

RenderSettings busy_settings() {
  RenderSettings s;
  s.width = 320;
  s.height = 180;
  s.ground = Ground{};
  s.ground->height = -0.9;
  s.caption = "Identical frames";
  s.cloth.wireframe = true;
  return s;
}

FrameContent busy_frame() {
  FrameContent frame = test::draped_cloth(20, 2.0, 0.5);
  frame.obstacles.push_back(test::sphere(Vec3::Zero(), 0.49));
  ObstacleShape cylinder;
  cylinder.kind = ObstacleShape::Kind::Cylinder;
  cylinder.center = Vec3(1.2, 0.5, -0.5);
  cylinder.axis = Vec3(1, 1, 0.5);
  cylinder.radius = 0.15;
  cylinder.half_length = 0.5;
  frame.obstacles.push_back(cylinder);
  frame.overlay_lines = info_overlay_lines("implicit_euler", frame.triangles.size(), 0.5);
  return frame;
}

TEST(render_frame, SameFrameTwiceIsBitIdentical) {
  Renderer renderer(busy_settings());
  std::vector<uint8_t> first, second, other;
  renderer.draw(busy_frame());
  renderer.read_rgb(first);
  renderer.draw(busy_frame());
  renderer.read_rgb(second);
  Renderer another(busy_settings());
  another.draw(busy_frame());
  another.read_rgb(other);
  ASSERT_EQ(first.size(), 320u * 180u * 3u);
  EXPECT_TRUE(first == second);
  EXPECT_TRUE(first == other);
}

TEST(render_frame, CameraIsFixedAtTheFirstFrame) {
  Renderer renderer(busy_settings());
  EXPECT_FALSE(renderer.camera().has_value());
  FrameContent frame = busy_frame();
  renderer.draw(frame);
  ASSERT_TRUE(renderer.camera().has_value());
  const Camera first = *renderer.camera();
  for (Vec3& p : frame.positions) p.z() -= 3.0;  // the cloth falls far
  renderer.draw(frame);
  EXPECT_EQ(renderer.camera()->eye, first.eye);
  EXPECT_EQ(renderer.camera()->target, first.target);
}

TEST(render_frame, WireframeDrawsTriangleEdges) {
  RenderSettings s = top_view(96, 96, 3);
  s.cloth.front_color = Vec3(0.9, 0.1, 0.1);
  s.cloth.wireframe_color = Vec3(0, 1, 0);
  auto greenish = [&](const std::vector<uint8_t>& rgb) {
    int n = 0;
    for (size_t i = 0; i < rgb.size(); i += 3) n += rgb[i + 1] > rgb[i] + 50;
    return n;
  };
  EXPECT_EQ(greenish(render(s, test::flat_cloth(4, 2.0))), 0);
  s.cloth.wireframe = true;
  EXPECT_GT(greenish(render(s, test::flat_cloth(4, 2.0))), 200);
}

TEST(render_frame, GroundShowsTheClothsShadow) {
  RenderSettings s = top_view(128, 128, 4);
  s.lights = {Light{Vec3(1, 0, -1), Vec3::Ones(), 1.0}};  // shadow shifted along +x
  s.ground = Ground{};
  s.ground->height = -0.5;
  s.ground->shadow = false;
  const FrameContent cloth = test::flat_cloth(4, 1.0);
  const std::vector<uint8_t> lit = render(s, cloth);
  s.ground->shadow = true;
  const std::vector<uint8_t> shadowed = render(s, cloth);
  // The cloth (x, y in [-0.5, 0.5]) casts onto x in [0, 1] of the ground, half of it visible.
  const auto [sx, sy] = project(s, Vec3(0.75, 0, -0.5));
  const auto [ox, oy] = project(s, Vec3(-0.75, 0, -0.5));
  EXPECT_LT(brightness(pixel(shadowed, 128, sx, sy)), brightness(pixel(lit, 128, sx, sy)) - 60);
  EXPECT_EQ(brightness(pixel(shadowed, 128, ox, oy)), brightness(pixel(lit, 128, ox, oy)));
}

// The shadow is the casters flattened onto the ground along the light: exact, and as sharp
// as the frame's anti-aliasing (MSAA 4 here) makes any edge.
TEST(render_frame, ShadowEdgeLiesWhereTheLightPutsIt) {
  RenderSettings s = top_view(256, 256, 4);
  s.lights = {Light{Vec3(1, 0, -1), Vec3::Ones(), 1.0}};  // shadow shifted along +x
  s.ground = Ground{};
  s.ground->height = -0.5;
  const std::vector<uint8_t> image = render(s, test::flat_cloth(4, 1.0));
  // The cloth (x in [-0.5, 0.5], z = 0) casts onto x in [0, 1] of the ground.
  const auto [dx, dy] = project(s, Vec3(0.7, 0, -0.5));
  const auto [lx, ly] = project(s, Vec3(1.4, 0, -0.5));
  const int dark = brightness(pixel(image, 256, dx, dy));
  const int lit = brightness(pixel(image, 256, lx, ly));
  ASSERT_GT(lit, dark + 60);
  const double edge = project(s, Vec3(1.0, 0, -0.5)).first + 0.5;  // in pixels, from the left
  for (int x = dx; x <= lx; ++x) {
    const int b = brightness(pixel(image, 256, x, dy));
    if (x + 0.5 < edge - 1.0) {
      EXPECT_EQ(b, dark) << "column " << x;
    } else if (x + 0.5 > edge + 1.0) {
      EXPECT_EQ(b, lit) << "column " << x;
    }
  }
}

// Ground pixels in the columns of x in (0.5, 1) m (the ground beyond the cloth's edge, on
// the row y = 0) at least 60 darker than in full light.
int shadowed_beyond_the_cloth(const RenderSettings& s, const std::vector<uint8_t>& image) {
  const int w = s.width;
  const auto [ex, ey] = project(s, Vec3(0.5, 0, s.ground->height));
  const auto [fx, fy] = project(s, Vec3(1.0, 0, s.ground->height));
  const int lit = brightness(pixel(image, w, fx + 20, fy));
  int n = 0;
  for (int x = ex + 1; x <= fx; ++x) n += brightness(pixel(image, w, x, ey)) < lit - 60;
  return n;
}

// Cloth a little above the ground, the light at 45 degrees: beyond its edge shows a band of
// shadow as wide as the cloth is high.
TEST(render_frame, ShadowOfClothNearTheGroundIsABandAsWideAsItsHeight) {
  RenderSettings s = top_view(256, 256, 4);
  s.lights = {Light{Vec3(1, 0, -1), Vec3::Ones(), 1.0}};  // shadow shifted along +x
  s.ground = Ground{};
  const FrameContent cloth = test::flat_cloth(4, 1.0);
  for (const double height : {0.08, 0.02}) {
    s.ground->height = -height;
    const double pixels_per_m =
        project(s, Vec3(1, 0, -height)).first - project(s, Vec3(0, 0, -height)).first;
    EXPECT_NEAR(shadowed_beyond_the_cloth(s, render(s, cloth)), height * pixels_per_m, 1.5) << height;
  }
}

// Half a sphere under the ground casts nothing: flattened along the light, that half would
// darken the ground on the side the light comes from.
TEST(render_frame, WhatIsUnderTheGroundCastsNoShadow) {
  RenderSettings s = top_view(256, 256, 4);
  s.lights = {Light{Vec3(1, 0, -1), Vec3::Ones(), 1.0}};
  s.ground = Ground{};
  s.ground->height = 0.0;
  FrameContent frame;
  frame.obstacles.push_back(test::sphere(Vec3::Zero(), 0.5));
  const std::vector<uint8_t> shadowed = render(s, frame);
  s.ground->shadow = false;
  const std::vector<uint8_t> lit = render(s, frame);
  // Beside the sphere towards the light: the lower half's flattened outline would reach
  // x = -0.71 m there.
  const auto [ux, uy] = project(s, Vec3(-0.6, 0, 0));
  EXPECT_EQ(brightness(pixel(shadowed, 256, ux, uy)), brightness(pixel(lit, 256, ux, uy)));
  // Beside it away from the light, the upper half's shadow (out to x = 0.71 m).
  const auto [sx, sy] = project(s, Vec3(0.6, 0, 0));
  EXPECT_LT(brightness(pixel(shadowed, 256, sx, sy)), brightness(pixel(lit, 256, sx, sy)) - 60);
}

// Seen at an angle, a sphere half under the ground shows only its upper half: the ground
// is drawn over the lower half (not left to the colour clear of its flat part).
TEST(render_frame, GroundHidesWhatReachesUnderIt) {
  RenderSettings s = test::plain_settings(256, 192);
  s.camera.eye = Vec3(0, -3, 1.5);
  s.camera.target = Vec3::Zero();
  s.camera.fov_deg = 40;
  s.ground = Ground{};
  s.ground->height = 0.0;
  s.ground->shadow = false;
  FrameContent sunk;
  sunk.obstacles.push_back(test::sphere(Vec3::Zero(), 0.5));
  const std::vector<uint8_t> image = render(s, sunk);
  const std::vector<uint8_t> bare = render(s, FrameContent{});
  // The lower half's front, 30 degrees under the ground: hidden by the ground.
  const auto [lx, ly] = project(s, Vec3(0, -0.5 * std::cos(M_PI / 6), -0.5 * std::sin(M_PI / 6)));
  EXPECT_EQ(brightness(pixel(image, 256, lx, ly)), brightness(pixel(bare, 256, lx, ly)));
  // The upper half's front shows.
  const auto [ux, uy] = project(s, Vec3(0, -0.5 * std::cos(M_PI / 6), 0.5 * std::sin(M_PI / 6)));
  EXPECT_NE(brightness(pixel(image, 256, ux, uy)), brightness(pixel(bare, 256, ux, uy)));
}

// The shadow is the same where the ground is drawn as a grid (a plane obstacle drawn after
// it needs the ground's depth) and where its shadow reaches the fade (the fading shader).
TEST(render_frame, ShadowIsTheSameOnEveryKindOfGround) {
  RenderSettings s = top_view(128, 128, 4);
  s.lights = {Light{Vec3(1, 0, -1), Vec3::Ones(), 1.0}};
  s.ground = Ground{};
  s.ground->height = -0.5;
  const FrameContent cloth = test::flat_cloth(4, 1.0);
  const std::vector<uint8_t> plain = render(s, cloth);
  const auto [sx, sy] = project(s, Vec3(0.75, 0, -0.5));
  const int shadow = brightness(pixel(plain, 128, sx, sy));
  EXPECT_LT(shadow, brightness(pixel(plain, 128, 128 - sx, sy)) - 60);
  FrameContent with_wall = cloth;  // a plane obstacle far to the side, edge-on to the camera
  ObstacleShape wall;
  wall.kind = ObstacleShape::Kind::Plane;
  wall.center = Vec3(-6, 0, 0);
  wall.axis = Vec3(1, 0, 0);
  with_wall.obstacles.push_back(wall);
  EXPECT_NEAR(brightness(pixel(render(s, with_wall), 128, sx, sy)), shadow, 3);
  // A small sphere far out, whose shadow falls beyond the fade's start (7.2 m from the
  // target: 0.45 of the ground's half size, 4 camera distances).
  FrameContent with_far_caster = cloth;
  with_far_caster.obstacles.push_back(test::sphere(Vec3(8, 0, 0), 0.1));
  EXPECT_NEAR(brightness(pixel(render(s, with_far_caster), 128, sx, sy)), shadow, 3);
}

// Bright pixels in rows [top, bottom) and columns [left, right).
int bright_pixels(const std::vector<uint8_t>& rgb, int width, int left, int top, int right,
                  int bottom) {
  int n = 0;
  for (int y = top; y < bottom; ++y) {
    for (int x = left; x < right; ++x) n += brightness(pixel(rgb, width, x, y)) > 450;
  }
  return n;
}

TEST(render_frame, CaptionAtTheTopAndInfoInTheCorner) {
  RenderSettings s = test::plain_settings(640, 360);
  s.camera.eye = Vec3(0, -3, 0);
  s.camera.target = Vec3::Zero();
  const std::vector<uint8_t> blank = render(s, FrameContent{});
  EXPECT_EQ(bright_pixels(blank, 640, 0, 0, 640, 360), 0);

  s.caption = "Caption";
  FrameContent frame;
  frame.overlay_lines = {"info line"};
  const std::vector<uint8_t> text = render(s, frame);
  EXPECT_GT(bright_pixels(text, 640, 220, 0, 420, 40), 40);   // caption, centred at the top
  EXPECT_GT(bright_pixels(text, 640, 0, 320, 160, 360), 40);  // info, bottom left
  EXPECT_EQ(bright_pixels(text, 640, 0, 60, 640, 300), 0);    // nothing in between
  EXPECT_EQ(bright_pixels(text, 640, 440, 300, 640, 360), 0);
}

class TempDir {
 public:
  TempDir() {
    std::string pattern = (std::filesystem::temp_directory_path() / "tissu-shaders-XXXXXX").string();
    path_ = mkdtemp(pattern.data());
  }
  ~TempDir() { std::filesystem::remove_all(path_); }
  const std::string& path() const { return path_; }
  void write(const std::string& name, const std::string& text) const {
    std::ofstream(path_ + "/" + name) << text;
  }

 private:
  std::string path_;
};

std::string render_error(const RenderSettings& s, const std::string& shader_dir) {
  try {
    Renderer renderer(s, shader_dir);
  } catch (const RenderError& e) {
    return e.what();
  }
  return "";
}

TEST(render_frame, BrokenShaderNamesFileAndLine) {
  TempDir dir;
  dir.write("cloth.frag",
            "#version 330 core\n"
            "out vec4 color;\n"
            "void main() {\n"
            "  color = vec4(1.0)\n"
            "}\n");
  const std::string message = render_error(test::plain_settings(32, 32), dir.path());
  EXPECT_EQ(message.rfind("shader compile error: " + dir.path() + "/cloth.frag:5:", 0), 0u)
      << message;
  EXPECT_EQ(message.find('\n'), std::string::npos);
}

TEST(render_frame, BrokenIncludedShaderNamesTheIncludedFile) {
  TempDir dir;
  dir.write("lighting.glsl", "// lights\n\nvec3 shade( {\n");
  const std::string message = render_error(test::plain_settings(32, 32), dir.path());
  EXPECT_EQ(message.rfind("shader compile error: " + dir.path() + "/lighting.glsl:3:", 0), 0u)
      << message;
}

TEST(render_frame, ReadBeforeDrawIsAnError) {
  Renderer renderer(test::plain_settings(32, 32));
  std::vector<uint8_t> rgb;
  EXPECT_THROW(renderer.read_rgb(rgb), RenderError);
}

}  // namespace
}  // namespace tissu
