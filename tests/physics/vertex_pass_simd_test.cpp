// The vectorised per-vertex pass of the explicit step
// (physics/vertex_pass_simd.h) against the scalar stages it replaces
// (finish_block_scalar: forces_stage2, integrate_vertices, check_vertex) on
// irregular and sliver meshes, with and without each force term the pass adds
// or sums (gravity, air damping, bending forces from stage 1, the membrane's
// strain-rate damping in the chunk buffers), for the three explicit
// integrators, and on every instruction set Highway built the pass for that
// this processor runs.
//
// Stated tolerance: every position and velocity component within 1e-12 of the
// largest scalar one (relative). The pass is built to do better, the scalar
// stages' bits, and BitsEqualScalar checks that too, along with the divergence
// check's findings.
#include "physics/vertex_pass_simd.h"

#include <gtest/gtest.h>
#include <hwy/targets.h>

#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "mesh/generate.h"
#include "physics/bending.h"
#include "physics/vertex_pass.h"
#include "test_meshes.h"

namespace tissu {
namespace {

constexpr double kRelativeTolerance = 1e-12;

struct Case {
  std::string name;
  testing::Sheet sheet; // a deformed, moving sheet with a few pinned vertices
};

Case make_case(const std::string &name, const TriMesh &mesh, unsigned seed) {
  Case c{name, {}};
  Model &m = c.sheet.model;
  m.triangles = mesh.triangles;
  m.rest_uv = mesh.rest_uv;
  m.material = testing::test_material();
  m.pinned.assign(mesh.rest_uv.size(), 0);
  for (size_t i = 0; i < m.pinned.size(); i += 37)
    m.pinned[i] = 1;
  precompute_rest(m);
  testing::deformed_moving(m.rest_uv, seed, c.sheet.state.x, c.sheet.state.v);
  return c;
}

std::vector<Case> cases() {
  std::vector<Case> out;
  out.push_back(make_case("irregular Delaunay",
                          generate_rectangle(1.0, 0.7, 997, true, 5), 6));
  out.push_back(
      make_case("slivers", generate_sliver_rectangle(1.0, 0.7, 1200), 7));
  return out;
}

// Force terms switched on and off, one bit each.
struct Terms {
  bool gravity, air_damping, bending, strain_rate_damping;
};

std::vector<Terms> all_terms() {
  std::vector<Terms> out;
  for (int bits = 0; bits < 16; ++bits) {
    out.push_back(
        {(bits & 1) != 0, (bits & 2) != 0, (bits & 4) != 0, (bits & 8) != 0});
  }
  return out;
}

std::string describe(const Terms &t, Integrator integrator) {
  return std::string(integrator_name(integrator)) +
         (t.gravity ? ", gravity" : "") +
         (t.air_damping ? ", air damping" : "") +
         (t.bending ? ", bending" : "") +
         (t.strain_rate_damping ? ", strain-rate damping" : "");
}

void set_terms(Model &model, const Terms &t, Integrator integrator) {
  model.integrator = integrator;
  model.dt = 1e-4; // s
  model.gravity.reset();
  if (t.gravity)
    model.gravity = Vec3(0.3, -1.2, -9.81);
  model.air_damping.reset();
  if (t.air_damping)
    model.air_damping = 0.7; // N*s/m^3
  model.bending.reset();
  if (t.bending) {
    model.bending = std::make_shared<BendingModel>(
        build_bending(model.triangles, model.rest_uv, 2e-4, 5e-4));
  }
  model.material.damping = t.strain_rate_damping ? 2e-3 : 0.0; // s
}

// One pass of every vertex block, scalar or vectorised, from the same stage 1.
struct Result {
  Vec3List x, v;
  std::vector<BlockCheck> checks;
};

Result pass(const Model &model, ForcePlan &plan, const Vec3List &x,
            const Vec3List &v, bool simd) {
  plan.plan(model);
  Vec3List f(x.size(), Vec3::Zero());
  forces_stage1(model, x, v, 0.0, 1, plan, f);
  Result r{x, v, std::vector<BlockCheck>(plan.num_blocks())};
  for (int b = 0; b < plan.num_blocks(); ++b) {
    if (simd) {
      finish_block_simd(model, plan, b, f, r.x, r.v, &r.checks[b]);
    } else {
      finish_block_scalar(model, plan, b, f, r.x, r.v, &r.checks[b]);
    }
  }
  return r;
}

void expect_same_checks(const std::vector<BlockCheck> &ref,
                        const std::vector<BlockCheck> &got) {
  ASSERT_EQ(ref.size(), got.size());
  for (size_t b = 0; b < ref.size(); ++b) {
    EXPECT_EQ(ref[b].first_bad, got[b].first_bad) << "block " << b;
    EXPECT_EQ(ref[b].bad_position, got[b].bad_position) << "block " << b;
    EXPECT_EQ(ref[b].fastest, got[b].fastest) << "block " << b;
    EXPECT_EQ(
        std::memcmp(&ref[b].top_speed2, &got[b].top_speed2, sizeof(double)), 0)
        << "block " << b << ": " << ref[b].top_speed2 << " vs "
        << got[b].top_speed2;
  }
}

void compare(const Vec3List &ref, const Vec3List &got, bool exact,
             const char *what) {
  double largest = 0.0;
  for (const Vec3 &p : ref)
    largest = std::max(largest, p.cwiseAbs().maxCoeff());
  ASSERT_GT(largest, 0.0) << what;
  for (size_t i = 0; i < ref.size(); ++i) {
    if (exact) {
      ASSERT_EQ(std::memcmp(ref[i].data(), got[i].data(), sizeof(Vec3)), 0)
          << what << " of vertex " << i << ": " << ref[i].transpose() << " vs "
          << got[i].transpose();
    } else {
      ASSERT_LE((ref[i] - got[i]).cwiseAbs().maxCoeff(),
                kRelativeTolerance * largest)
          << what << " of vertex " << i;
    }
  }
}

// Every case, set of terms and explicit integrator; `exact` asks for the same
// bits.
void check_all(bool exact) {
  for (Case &c : cases()) {
    ASSERT_NE(c.sheet.model.num_vertices() % 8, 0)
        << c.name << ": the last block needs a tail ("
        << c.sheet.model.num_vertices() << " vertices)";
    for (const Integrator integrator :
         {Integrator::ExplicitEuler, Integrator::SymplecticEuler,
          Integrator::BenameurDjedi}) {
      for (const Terms &t : all_terms()) {
        SCOPED_TRACE(c.name + ", " + describe(t, integrator));
        set_terms(c.sheet.model, t, integrator);
        ForcePlan plan;
        const Result ref =
            pass(c.sheet.model, plan, c.sheet.state.x, c.sheet.state.v, false);
        const Result got =
            pass(c.sheet.model, plan, c.sheet.state.x, c.sheet.state.v, true);
        compare(ref.x, got.x, exact, "position");
        compare(ref.v, got.v, exact, "velocity");
        if (exact)
          expect_same_checks(ref.checks, got.checks);
      }
    }
  }
}

TEST(VertexPassSimd, AgreesWithScalarWithinTolerance) {
  check_all(/*exact=*/false);
}

TEST(VertexPassSimd, BitsEqualScalar) { check_all(/*exact=*/true); }

// The divergence check's findings: a non-finite velocity or position inside a
// vector's lanes (after a faster vertex, which must then not count), and ties
// of the top speed (every vertex as fast: the first one of each block).
TEST(VertexPassSimd, DivergenceCheckAsScalar) {
  Case c = cases()[0];
  set_terms(c.sheet.model, {true, true, false, false},
            Integrator::SymplecticEuler);
  const double inf = std::numeric_limits<double>::infinity();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  struct Variant {
    std::string name;
    int vertex;
    Vec3 x, v; // replaced at `vertex` (NaN keeps the case's value)
  };
  const std::vector<Variant> variants = {
      {"non-finite velocity", 133, Vec3(nan, nan, nan), Vec3(0.0, inf, 0.0)},
      {"non-finite position", 262, Vec3(0.1, nan, 0.2), Vec3(nan, nan, nan)},
      {"fast vertex", 300, Vec3(nan, nan, nan), Vec3(40.0, 0.0, 0.0)},
  };
  for (const Variant &variant : variants) {
    SCOPED_TRACE(variant.name);
    Vec3List x = c.sheet.state.x, v = c.sheet.state.v;
    v[variant.vertex - 3] =
        Vec3(0.0, 0.0, 70.0); // faster, before the bad vertex
    for (int k = 0; k < 3; ++k) {
      if (!std::isnan(variant.x[k]))
        x[variant.vertex][k] = variant.x[k];
      if (!std::isnan(variant.v[k]))
        v[variant.vertex][k] = variant.v[k];
    }
    ForcePlan plan;
    const Result ref = pass(c.sheet.model, plan, x, v, false);
    const Result got = pass(c.sheet.model, plan, x, v, true);
    expect_same_checks(ref.checks, got.checks);
  }
  // Every vertex held (inverse masses zero), so every velocity stays as given.
  c.sheet.model.inv_mass.assign(c.sheet.model.inv_mass.size(), 0.0);
  for (const Vec3 &speed : {Vec3(0.1, -0.2, 0.3), Vec3::Zero().eval()}) {
    SCOPED_TRACE(speed.isZero() ? "every vertex at rest"
                                : "every vertex as fast");
    const Vec3List v(c.sheet.state.v.size(), speed);
    ForcePlan plan;
    const Result ref = pass(c.sheet.model, plan, c.sheet.state.x, v, false);
    const Result got = pass(c.sheet.model, plan, c.sheet.state.x, v, true);
    expect_same_checks(ref.checks, got.checks);
    EXPECT_EQ(got.checks[1].fastest, speed.isZero() ? -1 : plan.block_begin(1));
  }
}

// The check alone (check_block_simd, run by the step after the obstacles moved
// the vertices) against check_vertex on each vertex: ranges of every length
// modulo the vector width, a non-finite velocity or position after a faster
// vertex, ties of the top speed and every vertex at rest, on every instruction
// set the processor runs.
TEST(VertexPassSimd, BlockCheckAsScalarOnEveryTarget) {
  const Case c = cases()[0];
  const double inf = std::numeric_limits<double>::infinity();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const Vec3List &x0 = c.sheet.state.x, &v0 = c.sheet.state.v;
  struct Variant {
    std::string name;
    Vec3List x, v;
  };
  std::vector<Variant> variants = {{"moving sheet", x0, v0},
                                   {"non-finite velocity", x0, v0},
                                   {"non-finite position", x0, v0},
                                   {"every vertex as fast", x0,
                                    Vec3List(v0.size(), Vec3(0.1, -0.2, 0.3))},
                                   {"every vertex at rest", x0,
                                    Vec3List(v0.size(), Vec3::Zero())}};
  for (Variant &variant : {std::ref(variants[1]), std::ref(variants[2])}) {
    for (int i = 5; i < static_cast<int>(x0.size()); i += 61) {
      variant.v[i - 2] = Vec3(0.0, 0.0, 70.0); // faster, before the bad vertex
      if (variant.name == "non-finite velocity") {
        variant.v[i].y() = inf;
      } else {
        variant.x[i].z() = nan;
      }
    }
  }
  const std::vector<int64_t> targets = hwy::SupportedAndGeneratedTargets();
  ASSERT_FALSE(targets.empty());
  for (const int64_t target : targets) {
    hwy::SetSupportedTargetsForTest(target);
    SCOPED_TRACE(hwy::TargetName(target));
    for (const Variant &variant : variants) {
      SCOPED_TRACE(variant.name);
      for (int first = 0; first < 40; first += 3) {
        for (int length = 0; length < 140; length += 7) {
          const int end = std::min(static_cast<int>(x0.size()), first + length);
          BlockCheck ref, got;
          for (int i = first; i < end; ++i)
            check_vertex(i, variant.x[i], variant.v[i], ref);
          check_block_simd(variant.x, variant.v, first, end, got);
          SCOPED_TRACE("vertices " + std::to_string(first) + " to " +
                       std::to_string(end));
          expect_same_checks({ref}, {got});
        }
      }
    }
  }
  hwy::SetSupportedTargetsForTest(0);
}

// Every instruction set the pass was built for that this processor has: the
// same bits as the scalar stages on each width.
TEST(VertexPassSimd, BitsEqualScalarOnEveryTarget) {
  const std::vector<int64_t> targets = hwy::SupportedAndGeneratedTargets();
  ASSERT_FALSE(targets.empty());
  for (const int64_t target : targets) {
    hwy::SetSupportedTargetsForTest(target);
    SCOPED_TRACE(hwy::TargetName(target));
    check_all(/*exact=*/true);
  }
  hwy::SetSupportedTargetsForTest(0);
}

} // namespace
} // namespace tissu
