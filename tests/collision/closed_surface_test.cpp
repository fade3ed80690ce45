// Closed surfaces: exact signed distances of a box, a finely meshed sphere against the
// analytic one, the far-field shortcut, sharp features, and the errors for bad surfaces.
#include <gtest/gtest.h>

#include <random>

#include "collision/closed_surface.h"
#include "core/error.h"
#include "test_surfaces.h"

namespace tissu {
namespace {

using testing::box_surface;
using testing::icosphere;

ClosedSurface unit_box() {
  const testing::SurfaceData s = box_surface(Vec3(0, 0, 0), Vec3(1, 1, 1));
  return ClosedSurface(s.vertices, s.triangles, "box");
}

TEST(ClosedSurface, BoxDistancesAreExact) {
  const ClosedSurface box = unit_box();
  EXPECT_NEAR(box.volume(), 1.0, 1e-14);
  EXPECT_FALSE(box.reversed());
  SurfaceQuery q = box.closest(Vec3(0.5, 0.5, 2));
  EXPECT_DOUBLE_EQ(q.distance, 1.0);
  EXPECT_TRUE(q.normal.isApprox(Vec3(0, 0, 1)));
  q = box.closest(Vec3(0.5, 0.4, 0.45));
  EXPECT_DOUBLE_EQ(q.distance, -0.4);  // nearest face: y = 0
  EXPECT_TRUE(q.normal.isApprox(Vec3(0, -1, 0)));
  // Beyond a corner and an edge (the sign comes from pseudo-normals there).
  q = box.closest(Vec3(1.1, 1.2, 1.2));
  EXPECT_NEAR(q.distance, std::sqrt(0.01 + 0.04 + 0.04), 1e-15);
  EXPECT_TRUE(q.point.isApprox(Vec3(1, 1, 1)));
  q = box.closest(Vec3(-0.3, 0.5, -0.4));
  EXPECT_NEAR(q.distance, 0.5, 1e-15);
  EXPECT_TRUE(q.normal.isApprox(Vec3(-0.6, 0, -0.8)));
  // Inside, just below an edge and a corner.
  EXPECT_NEAR(box.closest(Vec3(0.99, 0.5, 0.98)).distance, -0.01, 1e-15);
  EXPECT_NEAR(box.closest(Vec3(0.97, 0.98, 0.99)).distance, -0.01, 1e-15);
}

TEST(ClosedSurface, SignIsRightEverywhereAroundABox) {
  const ClosedSurface box = unit_box();
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> u(-0.5, 1.5);
  for (int i = 0; i < 20000; ++i) {
    const Vec3 p(u(rng), u(rng), u(rng));
    const bool inside = (p.array() > 0.0).all() && (p.array() < 1.0).all();
    const Vec3 outside_part = (p.cwiseMax(Vec3::Zero()).cwiseMin(Vec3::Ones()) - p);
    const double exact = inside ? -std::min({p.x(), p.y(), p.z(), 1 - p.x(), 1 - p.y(), 1 - p.z()})
                                : outside_part.norm();
    EXPECT_NEAR(box.closest(p).distance, exact, 1e-14) << p.transpose();
  }
}

// A sphere of radius 1 meshed with 20 * 4^5 triangles: the mesh distance differs from the
// analytic one by at most the sagitta of its largest triangle, 1 - cos(angle), below
// 1.2e-3 here; the sign agrees wherever the point is farther than that from the sphere.
TEST(ClosedSurface, FineSphereMatchesTheAnalyticSphere) {
  const testing::SurfaceData s = icosphere(5, 1.0);
  const ClosedSurface sphere(s.vertices, s.triangles, "sphere");
  double sagitta = 0;
  for (const auto& e : sphere.edges()) {
    const double chord = (s.vertices[e[0]] - s.vertices[e[1]]).norm();
    sagitta = std::max(sagitta, chord * chord / 3.0);  // >= 1 - cos of the circumradius angle
  }
  ASSERT_LT(sagitta, 1.2e-3);
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(-1.6, 1.6);
  for (int i = 0; i < 3000; ++i) {
    const Vec3 p(u(rng), u(rng), u(rng));
    const double analytic = p.norm() - 1.0;
    const SurfaceQuery q = sphere.closest(p);
    EXPECT_NEAR(q.distance, analytic, sagitta) << p.transpose();
    if (std::fabs(analytic) > sagitta) {
      EXPECT_EQ(q.distance < 0, analytic < 0);
    }
    if (std::fabs(analytic) > 0.05) {
      EXPECT_GT(q.normal.dot(p.normalized()), 0.99);
    }
  }
  EXPECT_TRUE(sphere.sharp_edges().empty());
}

TEST(ClosedSurface, FarPointsGetTheSignAndABound) {
  const testing::SurfaceData s = icosphere(3, 0.5, Vec3(1, 2, 3));
  const ClosedSurface sphere(s.vertices, s.triangles, "sphere");
  std::mt19937 rng(6);
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  int far = 0;
  for (const double reach : {0.0, 0.01, 0.05, 0.2}) {
    for (int i = 0; i < 4000; ++i) {
      const Vec3 p = Vec3(1, 2, 3) + Vec3(u(rng), u(rng), u(rng));
      const SurfaceQuery exact = sphere.closest(p);
      const SurfaceQuery q = sphere.closest_within(p, reach);
      if (std::fabs(exact.distance) < reach) {
        EXPECT_EQ(q.distance, exact.distance);
        EXPECT_EQ(q.triangle, exact.triangle);
      } else {
        EXPECT_EQ(q.distance < 0, exact.distance < 0);
        EXPECT_GE(std::fabs(q.distance), reach);
        EXPECT_NE(q.distance, 0.0);
        EXPECT_LE(std::fabs(q.distance), std::fabs(exact.distance) + 1e-12);
        far += q.triangle < 0;
      }
    }
  }
  EXPECT_GT(far, 1000);  // the shortcut is taken
}

TEST(ClosedSurface, SharpEdgesOfABox) {
  const ClosedSurface box = unit_box();
  EXPECT_EQ(box.sharp_edges().size(), 12u);  // the face diagonals are flat
}

TEST(ClosedSurface, InwardFacingTrianglesAreReversed) {
  testing::SurfaceData s = box_surface(Vec3(0, 0, 0), Vec3(1, 1, 1));
  for (Tri& t : s.triangles) std::swap(t[1], t[2]);
  const ClosedSurface box(s.vertices, s.triangles, "box");
  EXPECT_TRUE(box.reversed());
  EXPECT_NEAR(box.closest(Vec3(0.5, 0.5, 0.5)).distance, -0.5, 1e-15);
  EXPECT_NEAR(box.closest(Vec3(0.5, 0.5, 1.5)).distance, 0.5, 1e-15);
}

// Two overlapping closed boxes: accepted, with the crossings reported; outside the union
// and near its outer surface the distance is exact.
TEST(ClosedSurface, SelfCrossingSurfaceIsReported) {
  const testing::SurfaceData b1 = box_surface(Vec3(0, 0, 0), Vec3(1, 1, 1));
  const testing::SurfaceData b2 = box_surface(Vec3(0.5, 0.5, 0.5), Vec3(1.5, 1.5, 1.5));
  Vec3List v = b1.vertices;
  TriList t = b1.triangles;
  for (const Vec3& p : b2.vertices) v.push_back(p);
  for (const Tri& tri : b2.triangles) t.push_back(tri + Tri::Constant(8));
  const ClosedSurface both(v, t, "both");
  EXPECT_TRUE(both.self_crossings().any());
  EXPECT_NEAR(both.closest(Vec3(2, 1, 1)).distance, 0.5, 1e-15);
  EXPECT_NEAR(both.closest(Vec3(0.2, 0.5, 0.5)).distance, -0.2, 1e-15);
  EXPECT_NEAR(both.closest(Vec3(1.4, 1.2, 1.2)).distance, -0.1, 1e-15);
  EXPECT_NEAR(both.closest(Vec3(-1, 0.5, 0.5)).distance, 1.0, 1e-15);
}

std::string error_of(const Vec3List& v, const TriList& t) {
  try {
    ClosedSurface surface(v, t, "body.off");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(ClosedSurface, BadSurfacesAreRefusedWithOneLine) {
  const testing::SurfaceData box = box_surface(Vec3(0, 0, 0), Vec3(1, 1, 1));
  // Open: one triangle missing.
  TriList open = box.triangles;
  open.pop_back();
  EXPECT_NE(error_of(box.vertices, open).find("body.off: not closed: the edge between vertex ids"),
            std::string::npos) << error_of(box.vertices, open);
  // Inconsistent: one triangle reversed.
  TriList flipped = box.triangles;
  std::swap(flipped[3][1], flipped[3][2]);
  EXPECT_NE(error_of(box.vertices, flipped).find("inconsistent orientation"), std::string::npos);
  // Non-manifold edge: a fin on edge 0-1 (a second closed box glued there would do too).
  Vec3List fin_v = box.vertices;
  fin_v.emplace_back(0.5, -1, -1);
  TriList fin = box.triangles;
  fin.emplace_back(0, 1, 8);
  EXPECT_NE(error_of(fin_v, fin).find("non-manifold: the edge between vertex ids 0 and 1 borders 3"),
            std::string::npos) << error_of(fin_v, fin);
  // Two boxes touching at one corner (vertex 7 of the first is vertex 0 of the second).
  testing::SurfaceData b2 = box_surface(Vec3(1, 1, 1), Vec3(2, 2, 2));
  Vec3List corner_v = box.vertices;
  TriList corner = box.triangles;
  for (int k = 1; k < 8; ++k) corner_v.push_back(b2.vertices[k]);
  for (Tri t : b2.triangles) {
    for (int k = 0; k < 3; ++k) t[k] = t[k] == 0 ? 7 : t[k] + 7;
    corner.push_back(t);
  }
  EXPECT_NE(error_of(corner_v, corner).find("separate fans of triangles meet at vertex id 7"),
            std::string::npos) << error_of(corner_v, corner);
  // Degenerate triangles and bad ids.
  Vec3List flat = box.vertices;
  flat[7] = Vec3(1, 1, 0.0);  // top corner pulled down onto the bottom one: zero-area faces
  EXPECT_NE(error_of(flat, box.triangles).find("zero area"), std::string::npos)
      << error_of(flat, box.triangles);
  TriList bad = box.triangles;
  bad[0][1] = 99;
  EXPECT_NE(error_of(box.vertices, bad).find("triangle 0: vertex id 99 out of range"),
            std::string::npos);
  EXPECT_NE(error_of(box.vertices, {}).find("contains no triangles"), std::string::npos);
}

}  // namespace
}  // namespace tissu
