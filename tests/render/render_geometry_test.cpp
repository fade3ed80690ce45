// Geometry, camera framing and text layout: the parts of the renderer that need no GL.
#include <gtest/gtest.h>

#include <cmath>

#include "render/camera.h"
#include "render/draw/cloth_geometry.h"
#include "render/draw/ground_geometry.h"
#include "render/gl/shader_files.h"
#include "render/scene_bounds.h"
#include "test_scenes.h"

namespace tissu {
namespace {

TEST(render_geometry, VertexNormalsAreAreaWeighted) {
  // Two triangles sharing vertex 0: a large one in z = 0 (normal +z) and a small
  // one in x = 0 (normal +x). The shared normal leans to the larger area.
  const Vec3List p = {Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(0, 2, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
  const TriList t = {Tri(0, 1, 2), Tri(0, 3, 4)};
  const Vec3List n = vertex_normals(p, t);
  // Areas 2 and 0.5: normal ~ (0.5, 0, 2) normalised.
  EXPECT_NEAR(n[0].x(), 0.5 / std::sqrt(4.25), 1e-12);
  EXPECT_NEAR(n[0].z(), 2.0 / std::sqrt(4.25), 1e-12);
  EXPECT_NEAR((n[1] - Vec3::UnitZ()).norm(), 0.0, 1e-12);
  EXPECT_NEAR((n[3] - Vec3::UnitX()).norm(), 0.0, 1e-12);
}

TEST(render_geometry, CornersAreThreePerTriangle) {
  const FrameContent cloth = test::flat_cloth(3, 1.0);
  std::vector<MeshVertex> corners;
  cloth_corners(cloth, corners);
  ASSERT_EQ(corners.size(), cloth.triangles.size() * 3);
  const Tri& t = cloth.triangles[4];
  EXPECT_FLOAT_EQ(corners[13].position.x, static_cast<float>(cloth.positions[t[1]].x()));
  EXPECT_FLOAT_EQ(corners[13].uv.y, static_cast<float>(cloth.rest_uv[t[1]].y()));
  EXPECT_FLOAT_EQ(corners[13].normal.z, 1.0f);
}

TEST(render_geometry, CheckClothRejectsBadIndices) {
  FrameContent cloth = test::flat_cloth(1, 1.0);
  cloth.triangles.push_back(Tri(0, 1, 9));
  try {
    check_cloth(cloth);
    FAIL() << "no error";
  } catch (const std::exception& e) {
    EXPECT_STREQ(e.what(), "frame content: triangle 2 uses vertex 9 of 4");
  }
}

// Projects p with the camera; true when it lies inside the view (|x|, |y| <= 1).
bool in_view(const Camera& c, double aspect, const Vec3& p) {
  const Vec3 f = (c.target - c.eye).normalized();
  const Vec3 r = f.cross(c.up).normalized();
  const Vec3 u = r.cross(f);
  const Vec3 q = p - c.eye;
  const double depth = q.dot(f);
  const double t = std::tan(c.fov_deg * M_PI / 360.0);
  return depth > 0 && std::abs(q.dot(r) / (depth * t * aspect)) <= 1.0 &&
         std::abs(q.dot(u) / (depth * t)) <= 1.0;
}

TEST(render_geometry, AutoCameraFramesClothObstaclesAndGround) {
  FrameContent frame = test::flat_cloth(4, 2.0, 1.0);
  frame.obstacles.push_back(test::sphere(Vec3(1.5, 0, 0.3), 0.3));
  const double aspect = 16.0 / 9.0;
  const Camera camera = auto_camera(frame, aspect, {}, -0.5);
  // Cloth and sphere, stretched down to the ground where the cloth will fall.
  const Box3 framed(Vec3(-1, -1, -0.5), Vec3(1.8, 1, 1));
  for (const Vec3& corner : box_corners(framed)) {
    EXPECT_TRUE(in_view(camera, aspect, corner)) << corner.transpose();
  }
  // Tight: from 80% of the distance some corner is out of view.
  const Camera closer{camera.target + 0.8 * (camera.eye - camera.target), camera.target,
                      camera.up, camera.fov_deg};
  bool some_outside = false;
  for (const Vec3& corner : box_corners(framed)) some_outside |= !in_view(closer, aspect, corner);
  EXPECT_TRUE(some_outside);
}

TEST(render_geometry, AutoCameraKeepsAGivenTarget) {
  CameraSettings settings;
  settings.target = Vec3(0, 0, 3);
  const Camera camera = auto_camera(test::flat_cloth(2, 1.0), 1.0, settings);
  EXPECT_EQ(camera.target, Vec3(0, 0, 3));
  EXPECT_TRUE(in_view(camera, 1.0, Vec3(0.5, 0.5, 0)));
}

// Area (m^2) of a part of the ground, checking each of its triangles on the way.
template <class CellCheck>
double ground_part_area(const IndexedMesh& part, CellCheck check) {
  double area = 0.0;
  for (size_t k = 0; k + 2 < part.indices.size(); k += 3) {
    const glm::vec3 a = part.vertices[part.indices[k]].position;
    const glm::vec3 b = part.vertices[part.indices[k + 1]].position;
    const glm::vec3 c = part.vertices[part.indices[k + 2]].position;
    const double twice = (b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y);
    EXPECT_GT(twice, 0.0) << "counter-clockwise seen from +z";
    for (const glm::vec3& p : {a, b, c}) {
      EXPECT_FLOAT_EQ(p.z, -0.3f);
      check(p);
    }
    area += 0.5 * twice;
  }
  return area;
}

TEST(render_geometry, GroundSplitsIntoOpaqueAndFadingCellsCoveringTheSquare) {
  const GroundRect square{glm::dvec2(-4.0, -3.0), glm::dvec2(4.0, 5.0)};
  const glm::dvec2 centre(0.0, 1.0);
  const double radius = 1.8;
  const SplitGround split = split_ground(square, -0.3, centre, radius, 16);
  auto in_disc = [&](const glm::vec3& p) {
    EXPECT_LE(std::hypot(p.x - centre.x, p.y - centre.y), radius + 1e-6);
  };
  const double opaque = ground_part_area(split.opaque, in_disc);
  const double fading = ground_part_area(split.fading, [](const glm::vec3&) {});
  EXPECT_NEAR(opaque + fading, 64.0, 1e-4);
  // The disc less a ragged edge at most a cell's diagonal (0.5 sqrt 2 m) wide is opaque.
  EXPECT_GE(opaque, M_PI * std::pow(radius - 0.5 * std::sqrt(2.0), 2));
  EXPECT_LE(opaque, M_PI * radius * radius);
}

TEST(render_geometry, GroundRingCoversTheSquareLessAPolygonInsideTheDisc) {
  // The fade's centre off the square's centre, so the corners' rays are not the even ones.
  const GroundRect square{glm::dvec2(-4.0, -3.0), glm::dvec2(4.0, 5.0)};
  const glm::dvec2 centre(0.3, 1.2);
  const double radius = 1.8;
  const std::optional<IndexedMesh> ring = ground_ring(square, -0.3, centre, radius, 16);
  ASSERT_TRUE(ring);
  // The ring's vertices lie on the disc's edge or on the square's sides.
  std::vector<glm::dvec2> polygon;
  for (size_t k = 0; k < ring->vertices.size(); ++k) {
    const glm::vec3 p = ring->vertices[k].position;
    if (k % 2 == 0) {
      EXPECT_NEAR(std::hypot(p.x - centre.x, p.y - centre.y), radius, 1e-5);
      polygon.emplace_back(p.x, p.y);
    } else {
      const bool on_side = std::abs(p.x - square.min.x) < 1e-5 || std::abs(p.x - square.max.x) < 1e-5 ||
                           std::abs(p.y - square.min.y) < 1e-5 || std::abs(p.y - square.max.y) < 1e-5;
      EXPECT_TRUE(on_side) << p.x << " " << p.y;
    }
  }
  ASSERT_GE(polygon.size(), 20u);  // 16 even rays and the 4 corners'
  double polygon_area = 0.0;
  for (size_t k = 0; k < polygon.size(); ++k) {
    const glm::dvec2 a = polygon[k] - centre, b = polygon[(k + 1) % polygon.size()] - centre;
    polygon_area += 0.5 * (a.x * b.y - a.y * b.x);
  }
  // Counter-clockwise triangles tiling the square less the polygon: no gap, no overlap.
  const double area = ground_part_area(*ring, [](const glm::vec3&) {});
  EXPECT_NEAR(area + polygon_area, 64.0, 1e-4);
  EXPECT_GT(polygon_area, 0.97 * M_PI * radius * radius);
  // The renderer's case: the fade centred on the square, 64 sides; the corners' rays are
  // even ones, taken once (no triangle without area).
  const GroundRect centred{glm::dvec2(-4.0, -4.0), glm::dvec2(4.0, 4.0)};
  const std::optional<IndexedMesh> even = ground_ring(centred, -0.3, glm::dvec2(0.0), radius, 64);
  ASSERT_TRUE(even);
  EXPECT_EQ(even->vertices.size(), 2u * 64u);
  const double even_polygon = 0.5 * 64 * radius * radius * std::sin(2.0 * M_PI / 64);
  EXPECT_NEAR(ground_part_area(*even, [](const glm::vec3&) {}) + even_polygon, 64.0, 1e-4);
  // A disc reaching past the square, or none: the grid's split is needed.
  EXPECT_FALSE(ground_ring(square, -0.3, centre, 4.0, 16));
  EXPECT_FALSE(ground_ring(square, -0.3, centre, 0.0, 16));
}

TEST(render_geometry, RectWithinDiscNeedsAllFourCorners) {
  const GroundRect rect{glm::dvec2(-0.7, -0.2), glm::dvec2(0.6, 0.9)};
  const glm::dvec2 centre(0.0, 0.3);
  // The farthest corner, (-0.7, 0.9), is sqrt(0.85) = 0.922 m away.
  EXPECT_TRUE(rect_within_disc(rect, centre, 0.923));
  EXPECT_FALSE(rect_within_disc(rect, centre, 0.921));
}

TEST(render_geometry, ShadowFootprintOfPointsHoldsTheirShadowWithinTheBoxes) {
  // A sheet 0.75 m above the ground at z = -0.3 and a sphere of radius 0.25 m under it; the
  // light comes down at an angle, as the default key light does.
  const Vec3 light(0.5, 1.5, -1.75);
  const std::vector<Vec3> sheet = {Vec3(-0.5, -0.5, 0.45), Vec3(0.5, -0.5, 0.45),
                                   Vec3(0.5, 0.5, 0.45), Vec3(-0.5, 0.5, 0.45)};
  Box3 sphere(Vec3::Constant(-0.25), Vec3::Constant(0.25));
  std::vector<Vec3> points = sheet;
  for (const Vec3& c : box_corners(sphere)) points.push_back(c);
  Box3 all = sphere;
  for (const Vec3& p : sheet) all.extend(p);
  const double h = -0.3, margin = 0.01;
  const std::optional<GroundRect> tight = shadow_footprint(points, light, h, margin);
  const std::optional<GroundRect> loose = shadow_footprint(box_corners(all), light, h, margin);
  ASSERT_TRUE(tight && loose);
  // Every point of the sheet and the sphere throws its shadow inside the tight rectangle.
  const Vec3 d = light.normalized();
  auto shadow_inside = [&](const Vec3& p) {
    const Vec3 q = p + d * ((h - p.z()) / d.z());
    return q.x() >= tight->min.x + margin && q.x() <= tight->max.x - margin &&
           q.y() >= tight->min.y + margin && q.y() <= tight->max.y - margin;
  };
  for (double u = 0.0; u <= 1.0; u += 0.125) {
    for (double v = 0.0; v <= 1.0; v += 0.125) {
      EXPECT_TRUE(shadow_inside(Vec3(-0.5 + u, -0.5 + v, 0.45)));
      const double polar = M_PI * u, azimuth = 2.0 * M_PI * v;
      EXPECT_TRUE(shadow_inside(0.25 * Vec3(std::sin(polar) * std::cos(azimuth),
                                            std::sin(polar) * std::sin(azimuth), std::cos(polar))));
    }
  }
  // The common box's footprint holds the tight one and is larger: the box's upper corners
  // above the sphere and its lower corners under the sheet hold no caster.
  EXPECT_LE(loose->min.x, tight->min.x);
  EXPECT_LE(loose->min.y, tight->min.y);
  EXPECT_GE(loose->max.x, tight->max.x);
  EXPECT_GE(loose->max.y, tight->max.y);
  auto area = [](const GroundRect& r) { return (r.max.x - r.min.x) * (r.max.y - r.min.y); };
  EXPECT_LT(area(*tight), 0.8 * area(*loose));
  // No points, or light from below: nothing to shadow.
  EXPECT_FALSE(shadow_footprint(std::vector<Vec3>{}, light, h, margin));
  EXPECT_FALSE(shadow_footprint(points, Vec3(0, 0, 1), h, margin));
}

TEST(render_geometry, GroundWithoutDiscIsAllFading) {
  const GroundRect square{glm::dvec2(-1.0, -1.0), glm::dvec2(1.0, 1.0)};
  const SplitGround split = split_ground(square, -0.3, glm::dvec2(0.0), 0.0, 4);
  EXPECT_TRUE(split.opaque.indices.empty());
  EXPECT_NEAR(ground_part_area(split.fading, [](const glm::vec3&) {}), 4.0, 1e-6);
}

TEST(render_geometry, ShaderLogNamesFileLineAndColumn) {
  const std::vector<std::string> files = {"/s/cloth.frag", "/s/lighting.glsl"};
  EXPECT_EQ(describe_shader_log("0:12(5): error: syntax error, unexpected ';'\n", files),
            "/s/cloth.frag:12:5: error: syntax error, unexpected ';'");
  EXPECT_EQ(describe_shader_log("1:3(1): error: `x' undeclared\n0:9(2): error: y\n", files),
            "/s/lighting.glsl:3:1: error: `x' undeclared (+1 more)");
  EXPECT_EQ(describe_shader_log("something odd\n", files), "/s/cloth.frag: something odd");
}

TEST(render_geometry, MissingShaderListsSearchedPaths) {
  try {
    find_shader("nothing.frag", {"/tmp/tissu-a", "/tmp/tissu-b"});
    FAIL() << "no error";
  } catch (const std::exception& e) {
    EXPECT_STREQ(e.what(),
                 "shader nothing.frag not found; searched /tmp/tissu-a/nothing.frag, "
                 "/tmp/tissu-b/nothing.frag");
  }
}

TEST(render_geometry, SearchListStartsWithTheExplicitDirectory) {
  const std::vector<std::string> dirs = shader_search_dirs("/explicit");
  ASSERT_GE(dirs.size(), 3u);
  EXPECT_EQ(dirs[0], "/explicit");
  EXPECT_NE(dirs[1].find("/shaders"), std::string::npos);
  EXPECT_EQ(dirs.back(), std::string(TISSU_SOURCE_DIR) + "/shaders");
}

}  // namespace
}  // namespace tissu
