// Cost of the implicit integrators on a hanging sheet of about 5000 triangles: Newton and
// conjugate-gradient iterations per step and milliseconds per step (one core), with the
// time split into Jacobian assembly, preconditioner, CG and residual evaluations.
//   ./build/bench/tissu_implicit_bench [triangles] [material] [seconds] [cg_tolerance]
//                                      [--solver NAME]...
// defaults: 5000 linen 0.5 1e-8; runs dt = 1/60 s and 1/600 s, backward Euler with one Newton
// iteration and with Newton to convergence, and BDF-2, with each preconditioner named by
// --solver (the scene's implicit.linear_solver names; default cholesky and
// block_jacobi_pcg). Times are processor time (std::clock).
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

#include "mesh/generate.h"
#include "physics/bending.h"
#include "physics/diagnostics.h"
#include "physics/implicit.h"
#include "physics/materials.h"
#include "physics/membrane.h"
#include "physics/step.h"

using namespace tissu;

namespace {

struct Setup {
  Model model;
  State state;
};

// A 1 m x 1 m sheet held at its two top corners, released flat and vertical (in the x-z
// plane) at rest: it stretches and sags under gravity and swings gently.
Setup make_setup(int triangles, const std::string& material) {
  TriMesh mesh = generate_rectangle(1.0, 1.0, triangles, /*irregular=*/true, /*seed=*/1);
  Setup s;
  s.model.triangles = mesh.triangles;
  s.model.rest_uv = mesh.rest_uv;
  s.model.material = *material_preset(material);
  s.model.gravity = Vec3(0, 0, -9.81);
  s.model.air_damping = 0.1;
  const int n = static_cast<int>(mesh.rest_uv.size());
  s.model.pinned.assign(n, 0);
  int top_left = 0, top_right = 0;
  for (int i = 0; i < n; ++i) {
    const Vec2& p = mesh.rest_uv[i];
    const Vec2& a = mesh.rest_uv[top_left];
    const Vec2& b = mesh.rest_uv[top_right];
    if (p.y() - p.x() > a.y() - a.x()) top_left = i;
    if (p.y() + p.x() > b.y() + b.x()) top_right = i;
  }
  s.model.pinned[top_left] = s.model.pinned[top_right] = 1;
  precompute_rest(s.model);
  if (s.model.material.bending > 0.0) {
    s.model.bending = std::make_shared<const BendingModel>(
        build_bending(s.model.triangles, s.model.rest_uv, s.model.material.bending,
                      s.model.material.bending_warp));
  }
  for (const Vec2& p : mesh.rest_uv) s.state.x.emplace_back(p.x(), 0.0, p.y());
  s.state.v.assign(n, Vec3::Zero());
  return s;
}

int usage(const char* program) {
  std::string names;
  for (LinearSolver s : kLinearSolvers) {
    names += std::string(names.empty() ? "" : ", ") + linear_solver_name(s);
  }
  std::fprintf(stderr,
               "usage: %s [triangles] [cotton|linen|silk] [seconds] [cg_tolerance] "
               "[--solver NAME]...\n  NAME: %s (default: cholesky and block_jacobi_pcg)\n",
               program, names.c_str());
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> positional;
  std::vector<LinearSolver> solvers;
  for (int k = 1; k < argc; ++k) {
    const std::string arg = argv[k];
    if (arg == "--help" || arg == "-h") return usage(argv[0]);
    if (arg == "--solver" && k + 1 < argc) {
      const std::string name = argv[++k];
      const auto* it = std::find_if(std::begin(kLinearSolvers), std::end(kLinearSolvers),
                                    [&](LinearSolver s) { return name == linear_solver_name(s); });
      if (it == std::end(kLinearSolvers)) return usage(argv[0]);
      solvers.push_back(*it);
    } else {
      positional.push_back(arg);
    }
  }
  if (solvers.empty()) solvers = {LinearSolver::Cholesky, LinearSolver::BlockJacobiPcg};
  const size_t args = positional.size();
  const int triangles = args > 0 ? std::atoi(positional[0].c_str()) : 5000;
  const std::string material = args > 1 ? positional[1] : "linen";
  const double seconds = args > 2 ? std::atof(positional[2].c_str()) : 0.5;  // s simulated per run
  const double cg_tolerance =
      args > 3 ? std::atof(positional[3].c_str()) : ImplicitOptions().cg_tolerance;
  if (args > 4 || triangles <= 0 || !material_preset(material) || !(seconds > 0.0) ||
      !(cg_tolerance > 0.0)) {
    return usage(argv[0]);
  }
  std::printf(
      "%s sheet, %.3g s of simulated time per run, newton_tolerance %.0e, cg_tolerance %.0e\n",
      material.c_str(), seconds, ImplicitOptions().newton_tolerance, cg_tolerance);
  std::printf("%-22s %-16s %-8s %-6s %6s %6s %8s %9s %6s %8s %8s %8s %8s %7s %6s\n", "solver", "integrator", "dt",
              "newton", "tris", "steps", "newton/s", "cg/step", "fact/s", "ms/step", "jac", "precond", "cg",
              "resid", "strain");
  struct Run {
    Integrator integrator;
    int newton;
  };
  for (LinearSolver solver : solvers)
  for (double dt : {1.0 / 60.0, 1.0 / 600.0}) {
    for (Run run : {Run{Integrator::BackwardEuler, 1}, Run{Integrator::BackwardEuler, 50},
                    Run{Integrator::Bdf2, 50}}) {
      Setup s = make_setup(triangles, material);
      s.model.integrator = run.integrator;
      s.model.dt = dt;
      s.model.implicit.max_newton_iterations = run.newton;
      s.model.implicit.cg_tolerance = cg_tolerance;
      s.model.implicit.linear_solver = solver;
      Workspace ws;
      const int steps = std::max(1, static_cast<int>(seconds / dt + 0.5));
      long newton = 0, cg = 0, factorizations = 0;
      double jac = 0, pre = 0, cgt = 0, res = 0;
      bool diverged = false;
      const std::clock_t t0 = std::clock();
      for (int k = 0; k < steps && !diverged; ++k) {
        diverged = step(s.model, s.state, ws).has_value();
        const ImplicitReport& r = *last_implicit_report(ws);
        newton += r.newton_iterations;
        cg += r.cg_iterations;
        factorizations += r.factorizations;
        jac += r.seconds_jacobian;
        pre += r.seconds_preconditioner;
        cgt += r.seconds_cg;
        res += r.seconds_residual;
      }
      const double total = static_cast<double>(std::clock() - t0) / CLOCKS_PER_SEC;
      std::printf("%-22s %-16s 1/%-6.0f %-6d %6d %6d %8.2f %9.1f %6.2f %8.2f %8.2f %8.2f %8.2f %7.2f %6.4f%s\n",
                  linear_solver_name(solver),
                  integrator_name(run.integrator), 1.0 / dt, run.newton, s.model.num_triangles(),
                  steps, double(newton) / steps, double(cg) / steps, double(factorizations) / steps, 1e3 * total / steps,
                  1e3 * jac / steps, 1e3 * pre / steps, 1e3 * cgt / steps, 1e3 * res / steps,
                  max_principal_strain(s.model, s.state.x), diverged ? " DIVERGED" : "");
      std::fflush(stdout);
    }
  }
  return 0;
}
