// Where an implicit run of a scene spends its steps: per step the substeps, Newton and CG
// iterations (totals over the substeps and any retry), the contacts at the end of the step
// and the step's processor time (one thread unless --threads). Totals at the end.
//   ./build/bench/tissu_implicit_profile SCENE [--set KEY=VALUE]... [--every N] [--detail]
//       [--threads N]   (default 1; times are processor time, summed over the threads)
// --detail adds, for each printed step, the substeps the approach rule predicted, those the
// step was planned with (fewer after a step that moved little) and those it took; its last
// substep's Newton iterations one by one (residual, line-search length, the barrier's
// longest step, the merit's change, vertices within dhat, CG iterations), factorizations,
// contact changes and the processor time of its stages. A run that diverges stops there,
// averages over the steps it took and exits with 3. The last line sums, over the steps, the
// processor time of each stage of their last substeps.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <exception>
#include <string>
#include <vector>

#include "physics/implicit.h"
#include "physics/step.h"
#include "scene/scene.h"

using namespace tissu;

namespace {

// One line of per-iteration values, each printed with format.
template <typename T>
void print_row(const char* label, const std::vector<T>& values, const char* format) {
  std::printf("       %-11s", label);
  for (const T& value : values) std::printf(format, value);
  std::printf("\n");
}

void print_detail(const ImplicitReport& r) {
  std::printf("       last substep: %d factorizations, %d contact changes, %d stuck\n",
              r.factorizations, r.contact_changes, r.stuck_contacts);
  print_row("residuals:", r.residuals, " %.2e");
  print_row("lengths:", r.step_lengths, " %.2f");
  print_row("max dv m/s:", r.velocity_changes, " %.1e");
  print_row("cap:", r.feasible_lengths, " %.2f");
  print_row("merit J:", r.merit_changes, " %.1e");
  print_row("barrier:", r.barrier_contacts, " %d");
  print_row("CG:", r.cg_per_iteration, " %d");
  std::printf("       ms: jacobian %.1f, preconditioner %.1f, cg %.1f, residual %.1f, contact %.1f\n",
              1e3 * r.seconds_jacobian, 1e3 * r.seconds_preconditioner, 1e3 * r.seconds_cg,
              1e3 * r.seconds_residual, 1e3 * r.seconds_contact);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s SCENE [--set KEY=VALUE]... [--every N] [--detail] [--threads N]\n",
                 argv[0]);
    return 2;
  }
  std::vector<std::string> overrides;
  int every = 1;
  bool detail = false;
  int threads = 1;
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--set" && i + 1 < argc) {
      overrides.push_back(argv[++i]);
    } else if (a == "--every" && i + 1 < argc) {
      every = std::atoi(argv[++i]);
    } else if (a == "--threads" && i + 1 < argc) {
      threads = std::max(1, std::atoi(argv[++i]));
    } else if (a == "--detail") {
      detail = true;
    } else {
      std::fprintf(stderr, "%s: unknown argument '%s'\n", argv[0], a.c_str());
      return 2;
    }
  }
  Scene scene;
  Simulation sim;
  try {
    scene = load_scene(argv[1], overrides);
    sim = build_simulation(scene);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 2;
  }
  Workspace ws;
  ws.threads = threads;
  std::printf("%6s %8s %4s %6s %6s %8s %8s\n", "step", "t s", "sub", "newton", "cg",
              "contacts", "ms");
  double total = 0.0;
  long long newton = 0, cg = 0, factorizations = 0, steps = 0;
  // Processor seconds of the stages of each step's last substep, summed.
  double jacobian = 0.0, preconditioner = 0.0, cg_seconds = 0.0, residual = 0.0, contact = 0.0;
  bool diverged = false;
  for (long long k = 0; k < scene.steps; ++k) {
    const int predicted = detail ? implicit_substeps(sim.model, sim.state) : 0;
    const std::clock_t t0 = std::clock();
    const auto divergence = step(sim.model, sim.state, ws);
    const double ms = 1e3 * static_cast<double>(std::clock() - t0) / CLOCKS_PER_SEC;
    total += ms;
    steps += 1;
    newton += ws.newton_iterations;
    cg += ws.cg_iterations;
    factorizations += ws.factorizations;
    const ImplicitReport* r = last_implicit_report(ws);
    if (r) {
      jacobian += r->seconds_jacobian;
      preconditioner += r->seconds_preconditioner;
      cg_seconds += r->seconds_cg;
      residual += r->seconds_residual;
      contact += r->seconds_contact;
    }
    if (r && (k % every == 0 || divergence)) {
      std::printf("%6lld %8.4f %4d %6d %6d %8d %8.1f\n", k, sim.state.t, ws.substeps,
                  ws.newton_iterations, ws.cg_iterations, r->contacts, ms);
      if (detail) {
        std::printf("       substeps predicted %d, planned %d, taken %d\n", predicted,
                    ws.planned_substeps, ws.substeps);
        print_detail(*r);
      }
    }
    if (divergence) {
      std::printf("diverged at t = %g s: %s\n", divergence->time, divergence->reason.c_str());
      diverged = true;
      break;
    }
  }
  // Per step over the steps taken: a run that diverged is averaged over its own steps.
  const double n = static_cast<double>(std::max(1LL, steps));
  std::printf(
      "total %.1f ms over %lld steps%s: %.2f ms/step, %.2f Newton/step, %.1f CG/step, %.1f "
      "CG/Newton, %.2f factorizations/step\n",
      total, steps, diverged ? " (DIVERGED)" : "", total / n, double(newton) / n, double(cg) / n,
      double(cg) / std::max(1LL, newton), double(factorizations) / n);
  std::printf(
      "last substeps' stages, ms/step: jacobian %.2f, preconditioner %.2f, cg %.2f, residual "
      "%.2f, contact %.2f\n",
      1e3 * jacobian / n, 1e3 * preconditioner / n, 1e3 * cg_seconds / n, 1e3 * residual / n,
      1e3 * contact / n);
  return diverged ? 3 : 0;
}
