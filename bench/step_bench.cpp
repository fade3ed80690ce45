// Speed of the force loop and of a whole explicit step, in ns per triangle per step, on
// irregular meshes of about 961, 4847 and 50,000 triangles (one core). Times are the
// process's CPU time (best of 5 repeats), so other load on the machine inflates them less
// than wall time would. With --threads N (N > 1) the whole step is also timed on N
// threads, in wall time (best of 5), with its speed-up over the one-thread wall time.
// Then the obstacle stage (scalar on every vertex, and with the vectorised near-test) and
// the membrane kernels side by side (scalar reference, vectorised) at about 5,000 and
// 50,000 triangles, and a whole step of a 1,000,000-triangle sheet on 1 and 2 threads with
// the memory its data take (skipped with --no-million), and the memory bandwidth a
// triad a[i] = b[i] + s c[i] over 3 x 128 MB reaches on 1 and 2 threads (the roofline's
// roof; double counting the write-allocate, so 32 bytes per element).
// --no-avx512 keeps the vector kernel to AVX2 or narrower (to compare widths).
//   ./build/bench/tissu_bench [--quick] [--threads N] [--no-million] [--no-avx512]
#include <hwy/targets.h>
#include <sys/resource.h>

#include <cstdio>
#include <ctime>
#include <cstdlib>
#include <cstring>
#include <algorithm>
#include <random>
#include <thread>
#include <vector>

#include "mesh/generate.h"
#include "physics/bending.h"
#include "physics/force_plan.h"
#include "physics/forces.h"
#include "physics/materials.h"
#include "physics/membrane.h"
#include "physics/membrane_layout.h"
#include "physics/membrane_simd.h"
#include "physics/obstacle_response.h"
#include "physics/step_scratch.h"
#include "physics/step.h"
#include "physics/vertex_pass.h"
#include "physics/vertex_pass_simd.h"
#include "step_setup.h"

using namespace tissu;
using namespace tissu::bench;

namespace {

template <class T>
double megabytes(const std::vector<T>& v) {
  return 1e-6 * static_cast<double>(v.capacity() * sizeof(T));
}

// Membrane forces of every triangle, ns per triangle, with the scalar and the vectorised
// kernel (one thread, CPU time, best of 5), undamped and with the preset's strain-rate
// damping (velocities set to small random values); then the bending forces (row "bending",
// still ns per triangle) with the scalar loop and the vectorised one (which, as in the
// step, first centres the positions into a padded buffer).
void compare_kernels(bool quick) {
  std::printf("\nmembrane kernels, one thread (vector kernel on %s)\n", membrane_simd_target());
  std::printf("%-10s %-8s %16s %16s %8s\n", "triangles", "term", "scalar ns/tri",
              "vector ns/tri", "ratio");
  for (int requested : {4847, 50000}) {
    Setup s = make_setup(requested);
    const int tris = s.model.num_triangles();
    std::mt19937 rng(2);
    std::uniform_real_distribution<double> u(-0.01, 0.01);
    for (Vec3& v : s.state.v) v = Vec3(u(rng), u(rng), u(rng));
    const int calls = std::max(5, (quick ? 2'000'000 : 20'000'000) / tris);
    Vec3List f(s.state.x.size());
    for (const bool damped : {false, true}) {
      s.model.material.damping = damped ? material_preset("cotton")->damping : 0.0;
      const Vec3List* v = damped ? &s.state.v : nullptr;
      const double scalar = best_seconds_per_call(
          [&] {
            std::fill(f.begin(), f.end(), Vec3::Zero());
            add_membrane_forces_scalar(s.model, s.state.x, v, 0, tris, VertexForces::of(f));
          },
          calls, 5);
      const double vector = best_seconds_per_call(
          [&] {
            std::fill(f.begin(), f.end(), Vec3::Zero());
            add_membrane_forces_simd(s.model, *s.model.membrane_layout, s.state.x, v, 0, tris,
                                     VertexForces::of(f));
          },
          calls, 5);
      std::printf("%-10d %-8s %16.2f %16.2f %7.2fx\n", tris, damped ? "damped" : "membrane",
                  scalar * 1e9 / tris, vector * 1e9 / tris, scalar / vector);
    }
    // Bending forces of every vertex (cotton's rigidity), per triangle as above.
    const BendingModel bending = build_bending(s.model.triangles, s.model.rest_uv,
                                               material_preset("cotton")->bending, -1.0);
    const int verts = s.model.num_vertices();
    const Vec3 origin = bending_origin(s.state.x);
    const double scalar = best_seconds_per_call(
        [&] {
          std::fill(f.begin(), f.end(), Vec3::Zero());
          add_bending_forces_scalar(bending, s.state.x, origin, 0, verts, VertexForces::of(f));
        },
        calls, 5);
    CenteredPositions centered;  // the step's buffer, kept from call to call
    const double vector = best_seconds_per_call(
        [&] {
          std::fill(f.begin(), f.end(), Vec3::Zero());
          center_positions(s.state.x, origin, centered);
          add_bending_forces(bending, centered, 0, verts, VertexForces::of(f));
        },
        calls, 5);
    std::printf("%-10d %-8s %16.2f %16.2f %7.2fx\n", tris, "bending", scalar * 1e9 / tris,
                vector * 1e9 / tris, scalar / vector);
  }
}

// The obstacle stage of the demo's obstacles (a sphere of radius 0.25 m touching the middle
// of the sheet, the ground 0.3 m below; thickness 5 mm) on the 4847-triangle sheet, ns per
// vertex (one thread, CPU time, best of 5): the scalar response on every free vertex
// (resolve_collisions), and the step's way, the near-test and the scalar response on the
// vertices it selects (collide_block).
void compare_obstacles(bool quick) {
  Setup s = make_setup(4847);
  Obstacle sphere, ground;
  sphere.kind = ObstacleKind::Sphere;
  sphere.center = Vec3(0.0, 0.0, -0.25 + 0.002);
  sphere.radius = 0.25;
  ground.kind = ObstacleKind::Plane;
  ground.center = Vec3(0.0, 0.0, -0.3);
  for (Obstacle* o : {&sphere, &ground}) o->thickness = 0.005;
  s.model.obstacles = {sphere, ground};
  s.model.pinned.assign(s.state.x.size(), 0);
  std::vector<PlacedObstacle> placed;
  for (const Obstacle& o : s.model.obstacles) placed.push_back(place_obstacle(o, 0.0));
  const int n = s.model.num_vertices();
  const int calls = quick ? 2000 : 20000;
  const CollisionResponse response = explicit_response(s.model);  // the step's
  const double scalar = best_seconds_per_call(
      [&] { resolve_collisions(s.model, 0.0, s.state.x, s.state.v); }, calls, 5);
  const double simd = best_seconds_per_call(
      [&] {
        for (int first = 0; first < n; first += ForcePlan::kVerticesPerBlock) {
          collide_block(placed, response, s.model.pinned, s.model.mass, first,
                        std::min(n, first + ForcePlan::kVerticesPerBlock), s.state.x,
                        s.state.v);
        }
      },
      calls, 5);
  std::printf("\nobstacle stage, %d vertices (sphere and ground), ns per vertex: scalar %.2f, "
              "near-test %.2f (%.1fx)\n",
              n, scalar * 1e9 / n, simd * 1e9 / n, scalar / simd);
  // The divergence check that follows the obstacle stage in a step, per vertex block.
  auto check_blocks = [&](bool vectorised) {
    for (int first = 0; first < n; first += ForcePlan::kVerticesPerBlock) {
      const int end = std::min(n, first + ForcePlan::kVerticesPerBlock);
      BlockCheck check;
      if (vectorised) {
        check_block_simd(s.state.x, s.state.v, first, end, check);
      } else {
        for (int i = first; i < end; ++i) check_vertex(i, s.state.x[i], s.state.v[i], check);
      }
    }
  };
  const double check_scalar = best_seconds_per_call([&] { check_blocks(false); }, calls, 5);
  const double check_simd = best_seconds_per_call([&] { check_blocks(true); }, calls, 5);
  std::printf("divergence check after it, ns per vertex: scalar %.2f, vectorised %.2f (%.1fx)\n",
              check_scalar * 1e9 / n, check_simd * 1e9 / n, check_scalar / check_simd);
}

// A whole explicit step of a 1,000,000-triangle sheet (regular mesh, gravity, air damping,
// the preset's strain-rate damping), best of 3 x 5 steps on 1 and 2 threads in wall time
// and in CPU time over all threads (which other load inflates less), and the memory its
// data take: model, state and the step's buffers.
void million_step() {
  const double t0 = clock_seconds(CLOCK_MONOTONIC);
  Setup s = make_setup(1'000'000, /*irregular=*/false);
  s.model.material.damping = material_preset("cotton")->damping;
  s.model.dt = 2e-6;
  const double setup_s = clock_seconds(CLOCK_MONOTONIC) - t0;
  std::printf("\n1M-triangle sheet: %d triangles, %d vertices (set up in %.1f s)\n",
              s.model.num_triangles(), s.model.num_vertices(), setup_s);
  for (int threads : {1, 2}) {
    Workspace ws;
    ws.threads = threads;
    step(s.model, s.state, ws);  // plans and allocates
    const double wall = best_seconds_per_call([&] { step(s.model, s.state, ws); }, 5, 3,
                                              CLOCK_MONOTONIC);
    const double cpu = best_seconds_per_call([&] { step(s.model, s.state, ws); }, 5, 3);
    std::printf("  step on %d thread%s: %.2f ms wall (%.2f ns/triangle), %.2f ms CPU over "
                "all threads\n",
                threads, threads > 1 ? "s" : "", 1e3 * wall, 1e9 * wall / s.model.num_triangles(),
                1e3 * cpu);
    if (threads == 2) {
      const Model& m = s.model;
      const MembraneLayout& l = *m.membrane_layout;
      const double model_mb = megabytes(m.triangles) + megabytes(m.rest_uv) + megabytes(m.rest) +
                              megabytes(m.mass) + megabytes(m.inv_mass) +
                              megabytes(m.lumped_area) + megabytes(m.pinned);
      const double layout_mb = 7 * megabytes(l.ru0) + 3 * megabytes(l.a);
      const double state_mb = megabytes(s.state.x) + megabytes(s.state.v);
      const StepScratch& scratch = *ws.scratch;
      const double step_mb = megabytes(scratch.f) + megabytes(scratch.x_old) +
                             megabytes(scratch.forces.partial) + megabytes(scratch.x_start);
      rusage usage;
      getrusage(RUSAGE_SELF, &usage);
      std::printf("  memory: model %.1f MB + vector layout %.1f MB + state %.1f MB + step "
                  "buffers %.1f MB = %.1f MB; process peak %.1f MiB\n",
                  model_mb, layout_mb, state_mb, step_mb,
                  model_mb + layout_mb + state_mb + step_mb, usage.ru_maxrss / 1024.0);
    }
  }
}

// Bandwidth of a[i] = b[i] + s c[i], GB/s (8 bytes read twice, written once and read for
// write-allocate per element), wall time best of 5, on `threads` threads each on its own
// contiguous share.
double triad_bandwidth(int threads) {
  const size_t n = size_t{16} << 20;  // 16 Mi doubles = 128 MB per array
  std::vector<double> a(n, 0.0), b(n, 1.0), c(n, 2.0);
  auto run = [&] {
    std::vector<std::thread> pool;
    for (int k = 0; k < threads; ++k) {
      pool.emplace_back([&, k] {
        const size_t lo = n * k / threads, hi = n * (k + 1) / threads;
        for (size_t i = lo; i < hi; ++i) a[i] = b[i] + 0.5 * c[i];
      });
    }
    for (std::thread& t : pool) t.join();
  };
  run();
  const double seconds = best_seconds_per_call(run, 1, 5, CLOCK_MONOTONIC);
  return 32.0 * static_cast<double>(n) / seconds * 1e-9;
}

}  // namespace

int main(int argc, char** argv) {
  bool quick = false;
  bool million = true;
  int threads = 1;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--quick") == 0) {
      quick = true;
    } else if (std::strcmp(argv[i], "--threads") == 0 && i + 1 < argc) {
      threads = std::max(1, std::atoi(argv[++i]));
    } else if (std::strcmp(argv[i], "--no-million") == 0) {
      million = false;
    } else if (std::strcmp(argv[i], "--no-avx512") == 0) {
      hwy::DisableTargets(HWY_AVX3 | HWY_AVX3_DL);
    } else {
      std::fprintf(stderr,
                   "usage: tissu_bench [--quick] [--threads N] [--no-million] [--no-avx512]\n");
      return 2;
    }
  }
  std::printf("%-10s %-10s %18s %18s %14s", "triangles", "vertices", "force ns/tri/step",
              "step ns/tri/step", "step ms");
  if (threads > 1) std::printf(" %14s %16s %10s", "1 thread wall", "threads wall", "speed-up");
  std::printf("\n");
  for (int requested : {961, 4847, 50000}) {
    Setup s = make_setup(requested);
    const int tris = s.model.num_triangles();
    const int calls = std::max(5, (quick ? 2'000'000 : 20'000'000) / tris);
    Vec3List f(s.state.x.size());
    const double force = best_seconds_per_call(
        [&] {
          std::fill(f.begin(), f.end(), Vec3::Zero());
          add_membrane_forces(s.model, s.state.x, nullptr, 0, tris, VertexForces::of(f));
        },
        calls, 5);
    Workspace ws;
    const double whole = best_seconds_per_call([&] { step(s.model, s.state, ws); }, calls, 5);
    std::printf("%-10d %-10d %18.1f %18.1f %14.4f", tris, s.model.num_vertices(),
                force * 1e9 / tris, whole * 1e9 / tris, whole * 1e3);
    if (threads > 1) {
      const double one_wall = best_seconds_per_call([&] { step(s.model, s.state, ws); }, calls,
                                                    5, CLOCK_MONOTONIC);
      Workspace shared;
      shared.threads = threads;
      const double many_wall = best_seconds_per_call(
          [&] { step(s.model, s.state, shared); }, calls, 5, CLOCK_MONOTONIC);
      std::printf(" %11.4f ms %10.4f ms (%d) %9.2fx", 1e3 * one_wall, 1e3 * many_wall, threads,
                  one_wall / many_wall);
    }
    std::printf("\n");
  }
  compare_obstacles(quick);
  compare_kernels(quick);
  if (million) million_step();
  std::printf("\nmemory bandwidth (triad): %.1f GB/s on 1 thread, %.1f GB/s on 2\n",
              triad_bandwidth(1), triad_bandwidth(2));
  return 0;
}
