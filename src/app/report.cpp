#include "app/report.h"

#include <cerrno>
#include <cstdio>

#include <algorithm>

#include "app/command_line.h"
#include "app/version.h"
#include "core/error.h"
#include "core/partial_file.h"
#include "physics/cloth_contact.h"

namespace tissu {

namespace {

nlohmann::ordered_json frame_row(const FrameStats& f) {
  nlohmann::ordered_json row = {{"step", f.step},
              {"time", f.time},
              {"kinetic_energy", f.kinetic_energy},
              {"elastic_energy", f.elastic_energy},
              {"potential_energy", f.potential_energy},
              {"max_speed", f.max_speed},
              {"max_strain", f.max_strain}};
  row["min_clearance"] = f.min_clearance ? nlohmann::ordered_json(*f.min_clearance) : nullptr;
  return row;
}

// How the run ended, in words.
std::string end_message(const RunResult& result) {
  switch (result.status) {
    case RunStatus::Ok: return "all steps done";
    case RunStatus::Stopped: return "stopped at --frames";
    case RunStatus::Interrupted: return "interrupted by a signal";
    case RunStatus::Diverged: break;
  }
  if (!result.divergence) return "diverged";
  const Divergence& d = *result.divergence;
  return "diverged at step " + std::to_string(d.step) + ", vertex " + std::to_string(d.vertex) +
         ": " + d.reason;
}

}  // namespace

nlohmann::ordered_json tissu_identity() {
  return {{"version", TISSU_VERSION}, {"git_commit", TISSU_GIT_COMMIT},
          {"git_modified", TISSU_GIT_MODIFIED}};
}

nlohmann::ordered_json make_report(const Scene& scene, const Model& model, const RunResult& result) {
  nlohmann::ordered_json report;
  report["scene"] = scene.name;
  report["scene_file"] = scene.file;
  report["tissu"] = tissu_identity();
  report["command_line"] = command_line();
  report["overrides"] = scene.overrides;
  report["vertices"] = model.num_vertices();
  report["triangles"] = model.num_triangles();
  report["integrator"] = integrator_name(model.integrator);
  report["dt"] = model.dt;
  report["threads"] = result.threads;
  report["steps_requested"] = scene.steps;
  report["steps_done"] = result.steps_done;
  report["simulated_time"] = static_cast<double>(result.steps_done) * model.dt;
  report["status"] = run_status_name(result.status);
  report["message"] = end_message(result);
  if (result.divergence) {
    const Divergence& d = *result.divergence;
    report["divergence"] = {
        {"step", d.step}, {"time", d.time}, {"vertex", d.vertex}, {"reason", d.reason}};
  } else {
    report["divergence"] = nullptr;
  }
  const StageTimes& t = result.times;
  report["wall_time_s"] = {{"simulate", t.simulate}, {"render", t.render},
                           {"readback", t.readback}, {"encode", t.encode}, {"encode_wait", t.encode_wait},
                           {"total", t.total}};
  report["ms_per_step"] = result.steps_done > 0 ? 1e3 * t.simulate / result.steps_done : 0.0;
  if (!is_explicit(model.integrator)) {
    report["newton_iterations"] = result.totals.newton_iterations;
    report["cg_iterations"] = result.totals.cg_iterations;
  }
  if (needs_cloth_contact(model)) {
    const double steps = std::max<double>(1.0, static_cast<double>(result.steps_done));
    report["contact"] = {{"cpu_s", result.totals.contact_seconds},
                         {"ms_per_step", 1e3 * result.totals.contact_seconds / steps},
                         {"proximity_impulses", result.totals.contact_proximities},
                         {"impacts", result.totals.contact_impacts},
                         {"list_rebuilds", result.totals.contact_rebuilds},
                         {"impact_zones", result.totals.contact_zones},
                         {"rigid_zones", result.totals.contact_rigid_zones},
                         {"unresolved_impacts", result.totals.contact_unresolved}};
    if (!is_explicit(model.integrator)) {
      report["contact"]["barrier_pairs"] = result.totals.barrier_pairs;
    }
  }
  if (!result.checks.empty()) {
    const CheckSummary summary = summarize_checks(result.checks);
    const FrameCheck* first = summary.first;
    nlohmann::ordered_json check = {{"frames_checked", result.checks.size()},
                                    {"frames_with_crossings", summary.frames_with_crossings},
                                    {"frames_with_obstacle_crossings",
                                     summary.frames_with_obstacle_crossings}};
    check["first"] = first ? nlohmann::ordered_json{{"step", first->step},
                                                    {"time", first->time},
                                                    {"cloth_pairs", first->cloth_pairs},
                                                    {"obstacle_pairs", first->obstacle_pairs},
                                                    {"what", first->first}}
                           : nlohmann::ordered_json(nullptr);
    report["check"] = check;
  }
  report["units"] = {{"time", "s"}, {"energy", "J"}, {"speed", "m/s"},
                     {"strain", "Green strain"}, {"clearance", "m"},
                     {"resolved_scene", "SI, as the scene format (docs/scenes.md)"}};
  // The scene as run: rerunning it alone gives the same frames.
  report["resolved_scene"] = scene.resolved;
  nlohmann::ordered_json rows = nlohmann::ordered_json::array();
  for (size_t i = 0; i < result.frames.size(); ++i) {
    nlohmann::ordered_json row = frame_row(result.frames[i]);
    if (i < result.checks.size()) {
      row["crossings"] = result.checks[i].cloth_pairs + result.checks[i].obstacle_pairs;
      row["obstacle_crossings"] = result.checks[i].obstacle_pairs;
    }
    rows.push_back(row);
  }
  report["frames"] = rows;
  if (result.end) report["end"] = frame_row(*result.end);
  return report;
}

}  // namespace tissu
