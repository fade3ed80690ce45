// Speed of the force loop and of a whole explicit step, in ns per triangle per step, on
// irregular meshes of about 961, 4847 and 50,000 triangles (one core). Times are the
// process's CPU time (best of 5 repeats), so other load on the machine inflates them less
// than wall time would.
//   ./build/bench/tissu_bench [--quick]
#include <cstdio>
#include <ctime>
#include <cstring>

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

double cpu_seconds() {
  timespec t;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

template <class F>
double best_seconds_per_call(F&& f, int calls, int repeats) {
  double best = 1e30;
  for (int r = 0; r < repeats; ++r) {
    const double t0 = cpu_seconds();
    for (int i = 0; i < calls; ++i) f();
    best = std::min(best, (cpu_seconds() - t0) / calls);
  }
  return best;
}

}  // namespace

int main(int argc, char** argv) {
  const bool quick = argc > 1 && std::strcmp(argv[1], "--quick") == 0;
  std::printf("%-10s %-10s %18s %18s %14s\n", "triangles", "vertices", "force ns/tri/step",
              "step ns/tri/step", "step ms");
  for (int requested : {961, 4847, 50000}) {
    Setup s = make_setup(requested);
    const int tris = s.model.num_triangles();
    const int calls = std::max(5, (quick ? 2'000'000 : 20'000'000) / tris);
    Vec3List f(s.state.x.size());
    const double force = best_seconds_per_call(
        [&] {
          std::fill(f.begin(), f.end(), Vec3::Zero());
          add_membrane_forces(s.model, s.state.x, nullptr, f);
        },
        calls, 5);
    Workspace ws;
    const double whole = best_seconds_per_call([&] { step(s.model, s.state, ws); }, calls, 5);
    std::printf("%-10d %-10d %18.1f %18.1f %14.4f\n", tris, s.model.num_vertices(),
                force * 1e9 / tris, whole * 1e9 / tris, whole * 1e3);
  }
  return 0;
}
