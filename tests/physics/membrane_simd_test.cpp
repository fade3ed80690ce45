// The vectorised membrane kernel (physics/membrane_simd.h) against the scalar reference
// (add_membrane_forces_scalar) on irregular and sliver meshes, with and without strain-rate
// damping, on triangle ranges of every length modulo the vector width, and on every
// instruction set Highway built the kernel for that this processor runs.
//
// Stated tolerance: every force component within 1e-12 of the largest scalar force
// component (relative). The kernel is built to do better, the scalar kernel's bits, and
// BitsEqualScalar checks that too (docs/physics.md).
#include "physics/membrane_simd.h"

#include <gtest/gtest.h>
#include <hwy/targets.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "mesh/generate.h"
#include "physics/membrane.h"
#include "test_meshes.h"

namespace tissu {
namespace {

constexpr double kRelativeTolerance = 1e-12;

struct Case {
  std::string name;
  Model model;
  Vec3List x, v;
};

// Deforms the rest positions and gives every vertex a velocity (test_meshes.h).
void deform(Case& c, unsigned seed) { testing::deformed_moving(c.model.rest_uv, seed, c.x, c.v); }

Case from_mesh(const std::string& name, const TriMesh& mesh, unsigned seed) {
  Case c;
  c.name = name;
  c.model.triangles = mesh.triangles;
  c.model.rest_uv = mesh.rest_uv;
  c.model.material = testing::test_material();
  precompute_rest(c.model);
  deform(c, seed);
  return c;
}

std::vector<Case> cases() {
  std::vector<Case> out;
  Case grid;
  grid.name = "jittered grid";
  grid.model = testing::grid_model(0.5, 0.3, 13, 7, 0.45, 3, nullptr);  // 182 triangles
  grid.model.material = testing::test_material();
  precompute_rest(grid.model);
  deform(grid, 4);
  out.push_back(std::move(grid));
  out.push_back(from_mesh("irregular Delaunay", generate_rectangle(1.0, 0.7, 997, true, 5), 6));
  out.push_back(from_mesh("slivers", generate_sliver_rectangle(1.0, 1.0, 1000), 7));
  return out;
}

// Triangle ranges [first, end): the whole mesh and pieces of every length 1..17 from
// starts that are not multiples of the vector width.
std::vector<std::pair<int, int>> ranges(int triangles) {
  std::vector<std::pair<int, int>> r{{0, triangles}};
  for (int length = 1; length <= 17; ++length) {
    const int first = (37 * length) % (triangles - length);
    r.emplace_back(first, first + length);
  }
  r.emplace_back(triangles - 5, triangles);
  r.emplace_back(1, triangles - 1);
  return r;
}

Vec3List forces(const Case& c, bool damped, int first, int end, bool simd) {
  Vec3List f(c.x.size(), Vec3::Zero());
  const Vec3List* v = damped ? &c.v : nullptr;
  if (simd) {
    add_membrane_forces_simd(c.model, *c.model.membrane_layout, c.x, v, first, end,
                             VertexForces::of(f));
  } else {
    add_membrane_forces_scalar(c.model, c.x, v, first, end, VertexForces::of(f));
  }
  return f;
}

// Checks every case, damping and range; `exact` asks for the same bits.
void check_all(bool exact) {
  for (const bool damping : {false, true}) {
    for (Case& c : cases()) {
      c.model.material.damping = damping ? 2e-3 : 0.0;  // s
      const int T = c.model.num_triangles();
      ASSERT_NE(T % 8, 0) << c.name << ": pick a count that is not a multiple of 8";
      for (const auto& [first, end] : ranges(T)) {
        SCOPED_TRACE(c.name + (damping ? ", damped" : "") + ", triangles [" +
                     std::to_string(first) + ", " + std::to_string(end) + ")");
        const Vec3List ref = forces(c, damping, first, end, false);
        const Vec3List got = forces(c, damping, first, end, true);
        double largest = 0.0;
        for (const Vec3& f : ref) largest = std::max(largest, f.cwiseAbs().maxCoeff());
        ASSERT_GT(largest, 0.0);
        for (size_t i = 0; i < ref.size(); ++i) {
          if (exact) {
            ASSERT_EQ(std::memcmp(ref[i].data(), got[i].data(), sizeof(Vec3)), 0)
                << "vertex " << i << ": " << ref[i].transpose() << " vs " << got[i].transpose();
          } else {
            ASSERT_LE((ref[i] - got[i]).cwiseAbs().maxCoeff(), kRelativeTolerance * largest)
                << "vertex " << i << ": " << ref[i].transpose() << " vs " << got[i].transpose();
          }
        }
      }
    }
  }
}

TEST(MembraneSimd, AgreesWithScalarWithinTolerance) {
  RecordProperty("target", membrane_simd_target());
  check_all(/*exact=*/false);
}

TEST(MembraneSimd, BitsEqualScalar) { check_all(/*exact=*/true); }

// Every instruction set the kernel was built for that this processor has (AVX-512, AVX2,
// SSE4, SSSE3, the portable scalar code): same bits as the scalar kernel on each width.
TEST(MembraneSimd, BitsEqualScalarOnEveryTarget) {
  const std::vector<int64_t> targets = hwy::SupportedAndGeneratedTargets();
  ASSERT_FALSE(targets.empty());
  std::string names;
  for (const int64_t target : targets) names += std::string(" ") + hwy::TargetName(target);
  std::printf("instruction sets tested:%s\n", names.c_str());
  for (const int64_t target : targets) {
    hwy::SetSupportedTargetsForTest(target);
    SCOPED_TRACE(hwy::TargetName(target));
    EXPECT_STREQ(membrane_simd_target(), hwy::TargetName(target));
    check_all(/*exact=*/true);
  }
  hwy::SetSupportedTargetsForTest(0);
}

// add_membrane_forces takes the vectorised kernel when the model has its layout and the
// scalar one when the layout is missing; both give the same forces.
TEST(MembraneSimd, DispatchUsesLayoutOrFallsBack) {
  Case c = std::move(cases()[0]);
  const int T = c.model.num_triangles();
  Vec3List with(c.x.size(), Vec3::Zero()), without(c.x.size(), Vec3::Zero());
  add_membrane_forces(c.model, c.x, nullptr, 0, T, VertexForces::of(with));
  c.model.membrane_layout.reset();
  add_membrane_forces(c.model, c.x, nullptr, 0, T, VertexForces::of(without));
  for (size_t i = 0; i < with.size(); ++i) ASSERT_EQ(with[i], without[i]) << "vertex " << i;
}

// A layout built for another mesh is refused rather than read out of bounds.
TEST(MembraneSimd, RefusesLayoutOfAnotherMesh) {
  Case a = std::move(cases()[0]);
  Model other = testing::grid_model(0.5, 0.3, 3, 2, 0.0, 1, nullptr);
  other.material = testing::test_material();
  precompute_rest(other);
  Vec3List f(a.x.size(), Vec3::Zero());
  EXPECT_THROW(add_membrane_forces_simd(a.model, *other.membrane_layout, a.x, nullptr, 0,
                                        a.model.num_triangles(), VertexForces::of(f)),
               std::logic_error);
}

}  // namespace
}  // namespace tissu
