// Parallel explicit steps: parallel_for hands out every item once in contiguous shares,
// and forces and whole steps are the same bits on any number of threads (the summation
// order depends on the mesh only; see ForcePlan in physics/force_plan.h).
#include "physics/parallel.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <atomic>
#include <cmath>
#include <cstring>
#include <map>
#include <mutex>
#include <optional>
#include <random>
#include <thread>
#include <vector>

#include "physics/air_damping.h"
#include "physics/bending.h"
#include "physics/force_plan.h"
#include "physics/forces.h"
#include "physics/gravity.h"
#include "physics/membrane.h"
#include "physics/wind.h"
#include "physics/step.h"
#include "physics/system_matrix.h"
#include "scene/scene.h"

namespace tissu {
namespace {

// Which thread ran each item.
std::vector<std::thread::id> run_items(int threads, int count, const double* cost) {
  std::vector<std::thread::id> ran_by(count);
  std::vector<std::atomic<int>> runs(count);
  parallel_for(threads, count, [&](int i) {
    runs[i].fetch_add(1);
    ran_by[i] = std::this_thread::get_id();
  }, cost);
  for (int i = 0; i < count; ++i) EXPECT_EQ(runs[i].load(), 1) << "item " << i;
  return ran_by;
}

TEST(ParallelFor, RunsEveryItemOnceInContiguousShares) {
  const std::vector<double> uneven = {1, 1, 1, 50, 1, 1, 1, 1, 30, 1, 1, 1, 1};
  for (int threads : {1, 2, 3, 8}) {
    for (int count : {0, 1, 2, 13, 100}) {
      for (bool weighted : {false, true}) {
        std::vector<double> cost(count, 1.0);
        for (int i = 0; i < count && weighted; ++i) cost[i] = uneven[i % uneven.size()];
        const auto ran_by = run_items(threads, count, weighted ? cost.data() : nullptr);
        std::map<std::thread::id, int> shares;  // thread -> number of runs of items
        for (int i = 0; i < count; ++i) {
          if (i == 0 || ran_by[i] != ran_by[i - 1]) shares[ran_by[i]] += 1;
        }
        for (const auto& [thread, runs] : shares) {
          EXPECT_EQ(runs, 1) << "a thread's items are not contiguous: threads " << threads
                             << ", count " << count;
        }
        EXPECT_LE(static_cast<int>(shares.size()), std::max(1, threads));
        if (threads == 1) {
          EXPECT_LE(shares.size(), 1u);
        }
      }
    }
  }
}

TEST(ParallelFor, BalancesSharesByCost) {
  // 2 threads, costs 10 + 1 x 10: the expensive item alone is half the work.
  std::vector<double> cost(11, 1.0);
  cost[0] = 10.0;
  const auto ran_by = run_items(2, 11, cost.data());
  for (int i = 1; i < 11; ++i) EXPECT_NE(ran_by[i], ran_by[0]) << "item " << i;
  // Equal costs: equal shares.
  std::vector<double> equal(100, 2.0);
  const auto even = run_items(2, 100, equal.data());
  int first_share = 0;
  while (first_share < 100 && even[first_share] == even[0]) ++first_share;
  EXPECT_EQ(first_share, 50);
}

// A scene with every force term and obstacle kind, and enough triangles for several
// chunks and vertex blocks and for steps to use 3 threads (2000 triangles per thread).
Simulation busy_scene(const char* integrator, double dt) {
  nlohmann::json doc = nlohmann::json::parse(R"({
    "name": "busy", "duration": 1.0,
    "cloth": {"mesh": {"generate": "rectangle", "size": [0.8, 0.8], "triangles": 6000,
                       "irregular": true, "seed": 11},
              "transform": {"translate": [0.0, 0.0, 0.25]},
              "material": "cotton",
              "pins": [{"box": {"min": [-1, 0.39, 0], "max": [-0.3, 1, 1]}}]},
    "gravity": [0.0, 0.0, -9.81],
    "air_damping": 0.3,
    "wind": {"velocity": [3.0, 1.0, 0.0], "drag": 2.0, "gust": {"amplitude": 0.5, "period": 0.2}},
    "position_correction": {"threshold": 1e-3, "iterations": 2},
    "obstacles": [
      {"sphere": {"center": [0.1, 0.0, 0.0], "radius": 0.2, "friction": 0.4,
                  "motion": {"velocity": [0.0, 0.0, 0.5]}}},
      {"cylinder": {"center": [-0.2, -0.25, 0.16], "axis": [1, 0, 0], "radius": 0.035,
                    "length": 0.3, "friction": 0.2}},
      {"plane": {"point": [0, 0, 0.18995], "normal": [0, 0, 1], "friction": 0.6}}
    ]
  })");
  doc["integrator"] = integrator;
  doc["dt"] = dt;
  // A scene's cloth starts outside its obstacles; this one is then lowered into the sphere
  // and the cylinder so that the collision stage has work from the first step.
  Simulation sim = build_simulation(parse_scene(doc, ""));
  for (Vec3& x : sim.state.x) x.z() -= 0.06;
  return sim;
}

bool same_bits(const Vec3List& a, const Vec3List& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(Vec3)) == 0;
}

TEST(ParallelForces, SameBitsOnAnyThreadCountAndEqualToTheTermsSummed) {
  Simulation sim = busy_scene("symplectic_euler", 4e-5);
  const Model& m = sim.model;
  ASSERT_TRUE(m.bending && m.wind && m.gravity && m.air_damping);
  ForcePlan plan;
  plan.plan(m);
  ASSERT_GE(plan.num_chunks(), 5);
  ASSERT_GE(plan.num_blocks(), 5);
  // A deformed, moving state.
  Vec3List x = sim.state.x, v(x.size());
  for (size_t i = 0; i < x.size(); ++i) {
    const double s = static_cast<double>(i);
    x[i] += 0.01 * Vec3(std::sin(s), std::cos(1.7 * s), std::sin(0.3 * s) * x[i].x());
    v[i] = Vec3(0.1 * std::cos(s), 0.2, -0.3 * std::sin(2.1 * s));
  }
  const double t = 0.13;
  Vec3List reference;
  for (int threads : {1, 2, 3, 7}) {
    Vec3List f;
    ForcePlan scratch;
    compute_forces(m, x, v, t, f, scratch, threads);
    if (threads == 1) {
      reference = f;
    } else {
      EXPECT_TRUE(same_bits(f, reference)) << threads << " threads";
    }
  }
  // The terms one by one, summed in another order: equal up to round-off.
  Vec3List terms(x.size(), Vec3::Zero());
  const VertexForces out = VertexForces::of(terms);
  const int nv = m.num_vertices(), nt = m.num_triangles();
  add_membrane_forces(m, x, &v, 0, nt, out);
  add_bending_forces(*m.bending, x, bending_origin(x), 0, nv, out);
  add_gravity(m, *m.gravity, 0, nv, out);
  add_air_damping(m, *m.air_damping, v, 0, nv, out);
  add_wind(m, *m.wind, x, v, t, 0, nt, out);
  double largest = 0.0, worst = 0.0;
  for (size_t i = 0; i < x.size(); ++i) {
    largest = std::max(largest, terms[i].norm());
    worst = std::max(worst, (terms[i] - reference[i]).norm());
  }
  EXPECT_GT(largest, 0.0);
  EXPECT_LT(worst, 1e-10 * largest);
}

// The implicit step's matrix (membrane blocks computed on several threads, then added to
// each block in triangle order) and its products: the same bits as on one thread.
TEST(ParallelAssembly, SystemMatrixAndProductSameBitsOnAnyThreadCount) {
  Simulation sim = busy_scene("backward_euler", 1.0 / 60.0);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Vec3List x = sim.state.x, v = sim.state.v;
  for (size_t i = 0; i < x.size(); ++i) {
    x[i] += 0.004 * Vec3(u(rng), u(rng), u(rng));  // stretched and compressed triangles
    v[i] = Vec3(u(rng), u(rng), u(rng));
  }
  Eigen::VectorXd p(3 * x.size());
  for (Eigen::Index k = 0; k < p.size(); ++k) p[k] = u(rng);
  std::vector<double> reference;
  Eigen::VectorXd reference_product;
  for (int threads : {1, 2, 3}) {
    SystemMatrix system;
    system.assemble(sim.model, x, v, 0.1, 1.0 / 60.0, /*project_psd=*/true, threads);
    Eigen::VectorXd product;
    system.matrix().multiply(p, product, threads);
    if (threads == 1) {
      reference = system.matrix().values();
      reference_product = product;
      continue;
    }
    const std::vector<double>& values = system.matrix().values();
    ASSERT_EQ(values.size(), reference.size());
    EXPECT_EQ(std::memcmp(values.data(), reference.data(), values.size() * sizeof(double)), 0)
        << threads << " threads";
    ASSERT_EQ(product.size(), reference_product.size());
    EXPECT_EQ(std::memcmp(product.data(), reference_product.data(),
                          product.size() * sizeof(double)),
              0)
        << threads << " threads";
  }
}

// Whole runs: explicit steps (forces, integration, position correction, collisions with a
// moving sphere, a cylinder and a plane) and implicit ones.
TEST(ParallelSteps, SameBitsOnAnyThreadCount) {
  struct Case {
    const char* integrator;
    double dt;
    int steps;
  };
  for (const Case& c : {Case{"symplectic_euler", 2e-5, 600}, Case{"explicit_euler", 1e-5, 200},
                        Case{"benameur_djedi", 2e-5, 200}, Case{"backward_euler", 2e-3, 4}}) {
    State reference;
    for (int threads : {1, 2, 3}) {
      Simulation sim = busy_scene(c.integrator, c.dt);
      ASSERT_EQ(force_threads(threads, sim.model), threads);  // the steps do use them
      Workspace ws;
      ws.threads = threads;
      for (int k = 0; k < c.steps; ++k) {
        ASSERT_FALSE(step(sim.model, sim.state, ws)) << c.integrator << " step " << k;
      }
      if (threads == 1) {
        reference = sim.state;
        // The collision stage had work: the cloth starts inside the sphere and the cylinder
        // and ends within 1 cm of every obstacle.
        const Simulation start = busy_scene(c.integrator, c.dt);
        for (size_t k = 0; k < sim.model.obstacles.size(); ++k) {
          const Obstacle& ob = sim.model.obstacles[k];
          double closest_start = 1e9, closest_end = 1e9;
          for (size_t i = 0; i < sim.state.x.size(); ++i) {
            Vec3 n;
            closest_start = std::min(closest_start, ob.signed_distance(start.state.x[i], 0.0, &n));
            closest_end = std::min(closest_end,
                                   std::abs(ob.signed_distance(sim.state.x[i], sim.state.t, &n)));
          }
          if (ob.kind != ObstacleKind::Plane) {
            EXPECT_LT(closest_start, 0.0) << obstacle_kind_name(ob.kind);
          }
          EXPECT_LT(closest_end, 1e-2) << c.integrator << ", " << obstacle_kind_name(ob.kind);
        }
      } else {
        EXPECT_TRUE(same_bits(sim.state.x, reference.x)) << c.integrator << ", " << threads;
        EXPECT_TRUE(same_bits(sim.state.v, reference.v)) << c.integrator << ", " << threads;
      }
    }
  }
}

// The divergence verdict is the serial one on any thread count: the first non-finite
// vertex wins over an earlier vertex that is only too fast.
TEST(ParallelSteps, DivergenceVerdictDoesNotDependOnThreads) {
  std::optional<Divergence> verdicts[2];
  for (int k = 0; k < 2; ++k) {
    Simulation sim = busy_scene("symplectic_euler", 2e-5);
    const int n = sim.model.num_vertices();
    ASSERT_FALSE(sim.model.pinned[1]);
    sim.state.v[1] = Vec3(300.0, 0.0, 0.0);  // too fast, in the first vertex block
    sim.state.v[n - 2] = Vec3(std::nan(""), 0.0, 0.0);  // non-finite, in the last block
    Workspace ws;
    ws.threads = k == 0 ? 1 : 3;
    verdicts[k] = step(sim.model, sim.state, ws);
    ASSERT_TRUE(verdicts[k]);
    int first_bad = -1;
    for (int i = 0; i < n && first_bad < 0; ++i) {
      if (!sim.state.x[i].allFinite() || !sim.state.v[i].allFinite()) first_bad = i;
    }
    EXPECT_EQ(verdicts[k]->vertex, first_bad);
    EXPECT_GT(first_bad, 1);
    EXPECT_NE(verdicts[k]->reason.find("non-finite"), std::string::npos) << verdicts[k]->reason;
  }
  EXPECT_EQ(verdicts[0]->vertex, verdicts[1]->vertex);
  EXPECT_EQ(verdicts[0]->reason, verdicts[1]->reason);

  // Only too fast (a speed limit every falling vertex exceeds): the same fastest vertex
  // on any thread count, and it is the first of the fastest.
  std::optional<Divergence> fastest[2];
  for (int k = 0; k < 2; ++k) {
    Simulation sim = busy_scene("symplectic_euler", 2e-5);
    sim.model.max_speed = 1e-9;  // m/s
    Workspace ws;
    ws.threads = k == 0 ? 1 : 3;
    fastest[k] = step(sim.model, sim.state, ws);
    ASSERT_TRUE(fastest[k]);
    EXPECT_EQ(fastest[k]->reason.rfind("speed ", 0), 0u) << fastest[k]->reason;
    double top = 0.0;
    int first = -1;
    for (int i = 0; i < sim.model.num_vertices(); ++i) {
      if (sim.state.v[i].squaredNorm() > top) {
        top = sim.state.v[i].squaredNorm();
        first = i;
      }
    }
    EXPECT_EQ(fastest[k]->vertex, first);
  }
  EXPECT_EQ(fastest[0]->vertex, fastest[1]->vertex);
  EXPECT_EQ(fastest[0]->reason, fastest[1]->reason);
}

}  // namespace
}  // namespace tissu
