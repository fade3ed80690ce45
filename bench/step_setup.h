// What the step benchmarks share: the benchmark's sheet (a 1 m cotton square, slightly
// stretched and wavy so that every strain component is non-zero, gravity and air damping,
// symplectic Euler at dt = 1e-5 s) and the timer (best of several repeats).
#pragma once

#include <time.h>

#include <algorithm>
#include <cmath>

#include "mesh/generate.h"
#include "physics/materials.h"
#include "physics/model.h"

namespace tissu::bench {

struct Setup {
  Model model;
  State state;
};

// The benchmark's sheet on `mesh` (a 1 m square in the plane z = 0).
inline Setup make_setup(const TriMesh& mesh) {
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
  for (Vec3& p : s.state.x) p = Vec3(1.01 * p.x(), 0.99 * p.y(), 0.01 * std::sin(7 * p.x()));
  s.state.v.assign(s.state.x.size(), Vec3::Zero());
  return s;
}

// The sheet on a generated mesh of about `triangles` triangles.
inline Setup make_setup(int triangles, bool irregular = true) {
  return make_setup(generate_rectangle(1.0, 1.0, triangles, irregular, /*seed=*/1));
}

inline double clock_seconds(clockid_t clock) {
  timespec t;
  clock_gettime(clock, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

// Seconds per call of f, the best of `repeats` runs of `calls` calls (process CPU time
// unless told otherwise).
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

}  // namespace tissu::bench
