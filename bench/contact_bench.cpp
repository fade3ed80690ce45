// Cost of the collision stage (physics/cloth_contact.h) against the membrane forces on the
// same mesh, in ns per triangle per step (one core, processor time). The scene is that of
// scenes/fold.json: a 0.8 m x 1.2 m sheet of cotton held upright, its lower edge just above
// the ground, let go: it falls onto the ground and piles up in folds over itself
// (self-collision thickness 3 mm, friction 0.3). Timed over the whole fall and over its
// last fifth (the sheet lying in folds, most of it in contact with itself), with
// symplectic Euler at a stable explicit step and with backward Euler at 1/60 s.
// Also counts what does not depend on the machine's load: stage calls, list builds and
// the pair distances measured for them, per step.
//   ./build/bench/tissu_contact_bench [--quick] [--only explicit|implicit]
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>

#include "mesh/generate.h"
#include "physics/forces.h"
#include "physics/materials.h"
#include "physics/membrane.h"
#include "physics/step.h"

using namespace tissu;

namespace {

constexpr double kThickness = 0.003;  // m

double cpu_seconds() {
  timespec t;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

struct Setup {
  Model model;
  State state;
};

// scenes/fold.json with `triangles` triangles.
Setup upright_sheet(int triangles) {
  TriMesh mesh = generate_rectangle(0.8, 1.2, triangles, /*irregular=*/true, /*seed=*/3);
  Setup s;
  s.model.triangles = mesh.triangles;
  s.model.rest_uv = mesh.rest_uv;
  s.model.material = *material_preset("cotton");
  s.model.gravity = Vec3(0, 0, -9.81);
  s.model.air_damping = 0.3;
  Obstacle ground;
  ground.kind = ObstacleKind::Plane;
  ground.center = Vec3::Zero();
  ground.axis = Vec3::UnitZ();
  ground.friction = 0.6;
  s.model.obstacles = {ground};
  s.model.self_collision = SelfCollision{kThickness, 0.3};
  precompute_rest(s.model);
  // Upright in the x-z plane, a little tilted so that it falls one way, lower edge at 2 cm.
  const double tilt = 8.0 * M_PI / 180.0;
  for (const Vec3& p : mesh.positions) {
    const double up = p.y() + 0.6;
    s.state.x.emplace_back(p.x(), up * std::sin(tilt), 0.02 + up * std::cos(tilt));
  }
  s.state.v.assign(s.state.x.size(), Vec3::Zero());
  return s;
}

struct Cost {
  double stage = 0, step = 0;            // ns per triangle per step, whole run
  double stage_late = 0, step_late = 0;  // the same over the last fifth
  double candidates = 0, rebuilds = 0, impacts = 0;  // per step, last fifth
  double calls = 0, builds = 0, distances = 0;       // per step, whole run
  double builds_late = 0, distances_late = 0;        // per step, last fifth
  bool crossed = false;
};

Cost run(Setup s, Integrator integrator, double dt, double seconds) {
  s.model.integrator = integrator;
  s.model.dt = dt;
  Workspace ws;
  const int steps = static_cast<int>(std::lround(seconds / dt));
  const int late = steps - steps / 5;
  Cost c;
  double stage = 0, total = 0, stage_late = 0, total_late = 0;
  for (int k = 0; k < steps; ++k) {
    const double t0 = cpu_seconds();
    step(s.model, s.state, ws);
    const double spent = cpu_seconds() - t0;
    stage += ws.contact_seconds;
    total += spent;
    c.calls += ws.contact.calls;
    c.builds += ws.contact.builds;
    c.distances += static_cast<double>(ws.contact.build_distances);
    if (k >= late) {
      stage_late += ws.contact_seconds;
      total_late += spent;
      c.candidates += ws.contact.candidates;
      c.rebuilds += ws.contact.rebuilt;
      c.builds_late += ws.contact.builds;
      c.distances_late += static_cast<double>(ws.contact.build_distances);
      c.impacts += ws.contact.impacts;
    }
  }
  const double tris = s.model.num_triangles();
  c.stage = 1e9 * stage / (steps * tris);
  c.step = 1e9 * total / (steps * tris);
  c.stage_late = 1e9 * stage_late / ((steps - late) * tris);
  c.step_late = 1e9 * total_late / ((steps - late) * tris);
  c.candidates /= steps - late;
  c.rebuilds /= steps - late;
  c.impacts /= steps - late;
  c.calls /= steps;
  c.builds /= steps;
  c.distances /= steps;
  c.builds_late /= steps - late;
  c.distances_late /= steps - late;
  return c;
}

double membrane_ns(const Setup& s) {
  const int tris = s.model.num_triangles();
  Vec3List f(s.state.x.size());
  double best = 1e30;
  for (int r = 0; r < 5; ++r) {
    const int calls = std::max(5, 2'000'000 / tris);
    const double t0 = cpu_seconds();
    for (int i = 0; i < calls; ++i) {
      std::fill(f.begin(), f.end(), Vec3::Zero());
      add_membrane_forces(s.model, s.state.x, nullptr, 0, tris, VertexForces::of(f));
    }
    best = std::min(best, (cpu_seconds() - t0) / calls);
  }
  return best * 1e9 / tris;
}

}  // namespace

int main(int argc, char** argv) {
  bool quick = false;
  const char* only = nullptr;  // "explicit" or "implicit": that row alone
  for (int a = 1; a < argc; ++a) {
    if (std::strcmp(argv[a], "--quick") == 0) quick = true;
    if (std::strcmp(argv[a], "--only") == 0 && a + 1 < argc) only = argv[++a];
  }
  std::printf("| triangles | integrator, dt | simulated s | membrane ns/tri/step | stage ns/tri/step "
              "(whole fall / last fifth) | stage / membrane (whole / last fifth) | whole step "
              "ns/tri (whole / last fifth) | pairs watched | steps with a list build | impacts "
              "per step | stage calls per step | list builds per step (whole / last fifth) | "
              "pair distances at builds per step (whole / last fifth) |\n"
              "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |\n");
  for (int requested : {5000, 50000}) {
    if (std::getenv("TISSU_BENCH_SMALL") && requested > 10000) continue;
    const bool big = requested > 10000;
    const Setup s = upright_sheet(requested);
    const double membrane = membrane_ns(s);
    auto row = [&](const char* name, Integrator integrator, double dt, double seconds) {
      const bool explicit_row = integrator == Integrator::SymplecticEuler;
      if (only && std::strcmp(only, explicit_row ? "explicit" : "implicit") != 0) return;
      const Cost c = run(s, integrator, dt, seconds);
      std::printf("| %d | %s %.3g s | %.2f | %.1f | %.1f / %.1f | %.2f / %.2f | %.1f / %.1f | %.0f | "
                  "%.3f | %.2f | %.2f | %.3f / %.3f | %.0f / %.0f |\n",
                  s.model.num_triangles(), name, dt, seconds, membrane, c.stage, c.stage_late,
                  c.stage / membrane, c.stage_late / membrane, c.step, c.step_late, c.candidates,
                  c.rebuilds, c.impacts, c.calls, c.builds, c.builds_late, c.distances,
                  c.distances_late);
      std::fflush(stdout);
    };
    const double seconds = quick ? 0.3 : (big ? 0.8 : 1.2);
    row("symplectic_euler", Integrator::SymplecticEuler, big ? 1e-5 : 4e-5, big && quick ? 0.1 : seconds);
    row("backward_euler", Integrator::BackwardEuler, 1.0 / 60.0, seconds);
  }
  return 0;
}
