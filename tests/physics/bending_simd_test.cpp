// The vectorised bending forces (physics/bending_simd.h) against the scalar loop
// (add_bending_forces_scalar): the same bits on irregular and sliver meshes, on vertex
// ranges of every length, from a non-zero starting force, and on every instruction set
// Highway built the kernel for that this processor runs.
#include "physics/bending_simd.h"

#include <gtest/gtest.h>
#include <hwy/targets.h>

#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "mesh/generate.h"
#include "physics/bending.h"

namespace tissu {
namespace {

struct Case {
  std::string name;
  BendingModel model;
  Vec3List x;   // m: a bent, noisy sheet
  Vec3List f0;  // N: the force the kernels add to
};

Case make_case(const std::string& name, const TriMesh& mesh, unsigned seed) {
  Case c;
  c.name = name;
  c.model = build_bending(mesh.triangles, mesh.rest_uv, 2e-4, 5e-4);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (const Vec2& p : mesh.rest_uv) {
    c.x.emplace_back(p.x() + 1e-3 * u(rng), p.y() + 1e-3 * u(rng),
                     0.1 * std::sin(5.0 * p.x() + 3.0 * p.y()) + 1e-3 * u(rng));
    c.f0.emplace_back(u(rng), u(rng), u(rng));
  }
  return c;
}

std::vector<Case> cases() {
  std::vector<Case> out;
  out.push_back(make_case("irregular Delaunay", generate_rectangle(1.0, 0.7, 997, true, 5), 6));
  out.push_back(make_case("slivers", generate_sliver_rectangle(1.0, 1.0, 1000), 7));
  return out;
}

void check_all() {
  for (const Case& c : cases()) {
    const int n = static_cast<int>(c.x.size());
    const Vec3 origin = bending_origin(c.x);
    CenteredPositions xc;
    center_positions(c.x, origin, xc);
    std::vector<std::pair<int, int>> ranges{{0, n}, {n - 1, n}, {0, 1}, {n - 5, n}};
    for (int length = 1; length <= 9; ++length) {
      ranges.emplace_back(31 * length, 31 * length + length);
    }
    for (const auto& [first, end] : ranges) {
      SCOPED_TRACE(c.name + ", vertices [" + std::to_string(first) + ", " +
                   std::to_string(end) + ")");
      Vec3List ref = c.f0, got = c.f0;
      add_bending_forces_scalar(c.model, c.x, origin, first, end, VertexForces::of(ref));
      add_bending_forces_simd(c.model, xc, first, end, VertexForces::of(got));
      for (int i = 0; i < n; ++i) {
        ASSERT_EQ(std::memcmp(ref[i].data(), got[i].data(), sizeof(Vec3)), 0)
            << "vertex " << i << ": " << ref[i].transpose() << " vs " << got[i].transpose();
      }
    }
  }
}

TEST(BendingSimd, BitsEqualScalarOnEveryTarget) {
  const std::vector<int64_t> targets = hwy::SupportedAndGeneratedTargets();
  ASSERT_FALSE(targets.empty());
  for (const int64_t target : targets) {
    hwy::SetSupportedTargetsForTest(target);
    SCOPED_TRACE(hwy::TargetName(target));
    check_all();
  }
  hwy::SetSupportedTargetsForTest(0);
}

// The forces are not trivially equal: the kernel changes them.
TEST(BendingSimd, ChangesTheForces) {
  const Case c = std::move(cases()[0]);
  Vec3List f = c.f0;
  add_bending_forces(c.model, c.x, bending_origin(c.x), 0, static_cast<int>(c.x.size()),
                     VertexForces::of(f));
  double change = 0.0;
  for (size_t i = 0; i < f.size(); ++i) change = std::max(change, (f[i] - c.f0[i]).norm());
  EXPECT_GT(change, 1e-6);
}

}  // namespace
}  // namespace tissu
