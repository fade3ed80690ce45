// Speed of the force loop and of a whole explicit step, in ns per triangle per step, on
// irregular meshes of about 961, 4847 and 50,000 triangles (one core). Times are the
// process's CPU time (best of 5 repeats), so other load on the machine inflates them less
// than wall time would. With --threads N (N > 1) the whole step is also timed on N
// threads, in wall time (best of 5), with its speed-up over the one-thread wall time.
//   ./build/bench/tissu_bench [--quick] [--threads N]
#include <cstdio>
#include <ctime>
#include <cstdlib>
#include <cstring>
#include <algorithm>

#include "mesh/generate.h"
#include "physics/forces.h"
#include "physics/materials.h"
#include "physics/membrane.h"
#include "physics/step.h"

using namespace tissu;

namespace {

struct Setup {
  Model model;
  State state;
};

Setup make_setup(int triangles) {
  TriMesh mesh = generate_rectangle(1.0, 1.0, triangles, /*irregular=*/true, /*seed=*/1);
  Setup s;
  s.model.triangles = mesh.triangles;
  s.model.rest_uv = mesh.rest_uv;
  s.model.material = *material_preset("cotton");
  s.model.material.damping = 0.0;
  s.model.gravity = Vec3(0, 0, -9.81);
  s.model.air_damping = 0.1;
  s.model.integrator = Integrator::SymplecticEuler;
  s.model.dt = 1e-5;
  precompute_rest(s.model);
  s.state.x = mesh.positions;
  // A slightly stretched, wavy sheet so every strain component is non-zero.
  for (Vec3& p : s.state.x) p = Vec3(1.01 * p.x(), 0.99 * p.y(), 0.01 * std::sin(7 * p.x()));
  s.state.v.assign(s.state.x.size(), Vec3::Zero());
  return s;
}

double clock_seconds(clockid_t clock) {
  timespec t;
  clock_gettime(clock, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

template <class F>
double best_seconds_per_call(F&& f, int calls, int repeats,
                             clockid_t clock = CLOCK_PROCESS_CPUTIME_ID) {
  double best = 1e30;
  for (int r = 0; r < repeats; ++r) {
    const double t0 = clock_seconds(clock);
    for (int i = 0; i < calls; ++i) f();
    best = std::min(best, (clock_seconds(clock) - t0) / calls);
  }
  return best;
}

}  // namespace

int main(int argc, char** argv) {
  bool quick = false;
  int threads = 1;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--quick") == 0) {
      quick = true;
    } else if (std::strcmp(argv[i], "--threads") == 0 && i + 1 < argc) {
      threads = std::max(1, std::atoi(argv[++i]));
    } else {
      std::fprintf(stderr, "usage: tissu_bench [--quick] [--threads N]\n");
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
  return 0;
}
