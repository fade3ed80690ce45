// The vectorised near-test of the collision stage (physics/obstacle_simd.h): with it, the
// stage gives the same bits as the scalar response on every free vertex
// (resolve_collisions), for spheres, cylinders and planes, static and moving; on vertices
// exactly at, just inside and just outside an obstacle's thickness; over whole explicit
// runs on irregular and sliver meshes; on every instruction set Highway built the test for
// that this processor runs. And the test selects no vertex that is clearly far.
#include "physics/obstacle_simd.h"

#include <gtest/gtest.h>
#include <hwy/targets.h>

#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "mesh/generate.h"
#include "physics/force_plan.h"
#include "physics/obstacle_response.h"
#include "physics/step.h"
#include "test_meshes.h"

namespace tissu {
namespace {

// m; radius + thickness and half length + thickness are exact in binary, so that some
// points are exactly at the thickness.
constexpr double kThickness = 1.0 / 256;

// One obstacle of each kind under a sheet in the x-y plane (at z = 0), touching it.
std::vector<Obstacle> obstacles_under_sheet() {
  std::vector<Obstacle> out(3);
  out[0].kind = ObstacleKind::Sphere;
  out[0].center = Vec3(0.05, -0.03, -0.25 - 0.001);
  out[0].radius = 0.25;
  out[1].kind = ObstacleKind::Cylinder;  // its caps and rims lie under the sheet too
  out[1].center = Vec3(-0.02, 0.04, -0.125 - 0.002);
  out[1].axis = Vec3(1.0, 0.3, 0.0).normalized();
  out[1].radius = 0.125;
  out[1].half_length = 0.15625;
  out[2].kind = ObstacleKind::Plane;
  out[2].center = Vec3(0.0, 0.0, -0.012);  // near the sheet at one corner
  out[2].axis = Vec3(0.02, -0.03, 1.0).normalized();
  for (Obstacle& o : out) {
    o.thickness = kThickness;
    o.friction = 0.3;
  }
  return out;
}

// The same obstacle moving: drifting and oscillating.
Obstacle moving(Obstacle o) {
  o.motion.velocity = Vec3(0.02, -0.01, 0.3);  // m/s
  o.motion.amplitude = Vec3(0.01, 0.004, 0.02);  // m
  o.motion.period = 0.013;                       // s
  return o;
}

std::string describe(const Obstacle& o) {
  return std::string(obstacle_kind_name(o.kind)) + (o.motion.moves() ? ", moving" : ", static");
}

// The obstacle stage over blocks with the near-test, as the step runs it.
void collide_blocks(const Model& model, double t, Vec3List& x, Vec3List& v) {
  std::vector<PlacedObstacle> placed;
  for (const Obstacle& o : model.obstacles) placed.push_back(place_obstacle(o, t));
  for (int first = 0; first < model.num_vertices(); first += ForcePlan::kVerticesPerBlock) {
    const int end = std::min(model.num_vertices(), first + ForcePlan::kVerticesPerBlock);
    collide_block(placed, explicit_response(model), model.pinned, model.mass, first, end, x, v);
  }
}

void expect_same_bits(const Vec3List& ref, const Vec3List& got, const char* what) {
  ASSERT_EQ(ref.size(), got.size());
  for (size_t i = 0; i < ref.size(); ++i) {
    ASSERT_EQ(std::memcmp(ref[i].data(), got[i].data(), sizeof(Vec3)), 0)
        << what << " of vertex " << i << ": " << ref[i].transpose() << " vs "
        << got[i].transpose();
  }
}

// Points around the thickness of `placed`: along rays from inside the obstacle, the last
// point closer than the thickness and the first one not, and those with one coordinate
// moved by 1 or 2 units in the last place.
Vec3List points_at_thickness(const PlacedObstacle& placed, unsigned seed) {
  const Obstacle& ob = *placed.obstacle;
  const auto distance = [&](const Vec3& p) {
    Vec3 n;
    return ob.signed_distance_from(p, placed.center, &n, placed.rotation);
  };
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Vec3List out;
  for (int ray = 0; ray < 60; ++ray) {
    const Vec3 dir = Vec3(u(rng), u(rng), u(rng)).normalized();
    // From the centre (a plane: a point of it), or a point inside near a cap's rim.
    Vec3 start = placed.center;
    if (ob.kind == ObstacleKind::Cylinder && ray % 2 == 1) {
      start += 0.9 * ob.half_length * (ray % 4 == 1 ? ob.axis : Vec3(-ob.axis));
    }
    if (ob.kind == ObstacleKind::Plane && dir.dot(ob.axis) <= 0.0) continue;
    double lo = 0.0, hi = 1.0;  // m along the ray: closer than the thickness, and not
    if (!(distance(start + hi * dir) >= ob.thickness)) continue;
    while (std::nextafter(lo, hi) < hi) {
      const double mid = 0.5 * (lo + hi);
      if (mid <= lo || mid >= hi) break;
      (distance(start + mid * dir) < ob.thickness ? lo : hi) = mid;
    }
    for (const double s : {lo, hi}) {
      const Vec3 p = start + s * dir;
      out.push_back(p);
      for (int c = 0; c < 3; ++c) {
        for (const double toward : {-INFINITY, INFINITY}) {
          Vec3 q = p;
          q[c] = std::nextafter(q[c], toward);
          out.push_back(q);
          q[c] = std::nextafter(q[c], toward);
          out.push_back(q);
        }
      }
    }
  }
  return out;
}

// For each kind, static and moving: the stage with the near-test moves the same vertices
// to the same bits as the scalar stage, and the points cover all three sides.
void check_thickness_points() {
  for (const Obstacle& base : obstacles_under_sheet()) {
    for (const Obstacle& ob : {base, moving(base)}) {
      SCOPED_TRACE(describe(ob));
      const double t = 0.0137;  // s
      const PlacedObstacle placed = place_obstacle(ob, t);
      Model model;
      model.obstacles = {ob};
      Vec3List x = points_at_thickness(placed, 11);
      x.push_back(Vec3(0.3, 0.2, 0.1));  // a tail for every lane count
      model.rest_uv.assign(x.size(), Vec2::Zero());
      model.pinned.assign(x.size(), 0);
      model.mass.assign(x.size(), 1.0);  // kg
      int at = 0, inside = 0, outside = 0;
      for (const Vec3& p : x) {
        Vec3 n;
        const double dist = ob.signed_distance_from(p, placed.center, &n, placed.rotation);
        at += dist == ob.thickness;
        inside += dist < ob.thickness;
        outside += dist > ob.thickness;
      }
      EXPECT_GT(at, 0);
      EXPECT_GT(inside, 10);
      EXPECT_GT(outside, 10);
      Vec3List v(x.size(), Vec3(0.1, -0.2, -0.5));
      Vec3List x_ref = x, v_ref = v;
      resolve_collisions(model, t, x_ref, v_ref);
      collide_blocks(model, t, x, v);
      expect_same_bits(x_ref, x, "position");
      expect_same_bits(v_ref, v, "velocity");
    }
  }
}

TEST(ObstacleSimd, SameBitsAtAndAroundTheThickness) { check_thickness_points(); }

// A sheet of a given mesh at z = 0, falling at 0.4 m/s, a few vertices pinned, stepped at
// dt (s).
testing::Sheet falling_sheet(const TriMesh& mesh, double dt) {
  testing::Sheet s;
  s.model.triangles = mesh.triangles;
  s.model.rest_uv = mesh.rest_uv;
  s.model.material = testing::test_material();
  s.model.pinned.assign(mesh.rest_uv.size(), 0);
  for (size_t i = 0; i < s.model.pinned.size(); i += 53) s.model.pinned[i] = 1;
  s.model.gravity = Vec3(0, 0, -9.81);
  s.model.integrator = Integrator::SymplecticEuler;
  s.model.dt = dt;
  precompute_rest(s.model);
  for (const Vec2& p : mesh.rest_uv) s.state.x.emplace_back(p.x(), p.y(), 0.0);
  s.state.v.assign(s.state.x.size(), Vec3(0, 0, -0.4));
  return s;
}

// N explicit steps with the obstacle: the same bits as N steps without it, each followed
// by the scalar stage on every free vertex.
void check_runs() {
  struct Case {
    std::string name;
    TriMesh mesh;
    double dt;  // s, below the mesh's explicit stability limit
  };
  const std::vector<Case> cases = {
      {"irregular Delaunay", generate_rectangle(0.5, 0.4, 997, true, 5), 1e-4},
      {"slivers", generate_sliver_rectangle(0.5, 0.4, 1200), 2e-6}};
  for (const auto& [name, mesh, dt] : cases) {
    for (const Obstacle& base : obstacles_under_sheet()) {
      for (const Obstacle& ob : {base, moving(base)}) {
        SCOPED_TRACE(name + ", " + describe(ob));
        testing::Sheet with = falling_sheet(mesh, dt);
        with.model.obstacles = {ob};
        testing::Sheet without = falling_sheet(mesh, dt);
        Workspace ws_with, ws_without;
        int touching = 0;
        for (int s = 0; s < 150; ++s) {
          const auto divergence = step(with.model, with.state, ws_with);
          ASSERT_FALSE(divergence) << divergence->reason << " at step " << s;
          step(without.model, without.state, ws_without);
          const Vec3List x_free = without.state.x;
          resolve_collisions(with.model, without.state.t, without.state.x, without.state.v);
          for (size_t i = 0; i < x_free.size(); ++i) touching += x_free[i] != without.state.x[i];
        }
        EXPECT_GT(touching, 100) << "the sheet must meet the obstacle";
        expect_same_bits(without.state.x, with.state.x, "position");
        expect_same_bits(without.state.v, with.state.v, "velocity");
      }
    }
  }
}

TEST(ObstacleSimd, RunsGiveTheScalarBits) { check_runs(); }

// Every instruction set the test was built for that this processor has.
TEST(ObstacleSimd, SameBitsOnEveryTarget) {
  for (const int64_t target : hwy::SupportedAndGeneratedTargets()) {
    hwy::SetSupportedTargetsForTest(target);
    SCOPED_TRACE(hwy::TargetName(target));
    check_thickness_points();
  }
  hwy::SetSupportedTargetsForTest(0);
}

// The test is a filter: vertices clearly farther than the thickness are not selected, and
// a mesh obstacle (answered by its own scalar path) selects them all.
TEST(ObstacleSimd, SelectsOnlyVerticesNearAnObstacle) {
  std::vector<Obstacle> obstacles = obstacles_under_sheet();
  std::vector<PlacedObstacle> placed;
  for (const Obstacle& o : obstacles) placed.push_back(place_obstacle(o, 0.0));
  Vec3List x;
  for (int i = 0; i < ForcePlan::kVerticesPerBlock; ++i) x.emplace_back(0.01 * i, 0.0, 0.2);
  const double gap = 1e-9;  // m beyond the thickness
  x[5] = placed[2].center;  // on the plane
  x[70] = placed[0].center + Vec3(0, 0, obstacles[0].radius + kThickness + gap);
  std::vector<int> selected(x.size());
  const int count = select_near_obstacles(placed, x, 0, static_cast<int>(x.size()),
                                          selected.data());
  ASSERT_EQ(count, 1);
  EXPECT_EQ(selected[0], 5);

  Obstacle mesh;
  mesh.kind = ObstacleKind::Mesh;
  placed.push_back(PlacedObstacle{&mesh});
  EXPECT_EQ(select_near_obstacles(placed, x, 0, static_cast<int>(x.size()), selected.data()),
            static_cast<int>(x.size()));
}

}  // namespace
}  // namespace tissu
