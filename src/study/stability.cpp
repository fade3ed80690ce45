#include "study/stability.h"

#include <algorithm>
#include <chrono>
#include <map>
#include <ostream>
#include <sstream>

#include "study/output.h"

namespace tissu {

namespace {

std::string failure_text(const ProbeResult& p) {
  std::string s = probe_status_name(p.status);
  if (p.failure) {
    s += " at step " + std::to_string(p.failure->step) + " (t = " + sig(p.failure->time) +
         " s), vertex " + std::to_string(p.failure->vertex) + ": " + p.failure->reason;
  }
  return s;
}

}  // namespace

std::vector<StabilityRow> run_stability(const Scene& scene, const Simulation& base,
                                        const StabilityOptions& options) {
  std::vector<StabilityRow> rows;
  const double duration = static_cast<double>(scene.steps) * scene.dt;
  for (Integrator integrator : options.integrators) {
    StabilityRow row;
    row.scene_name = scene.name;
    row.scene_file = scene.file;
    row.vertices = base.model.num_vertices();
    row.triangles = base.model.num_triangles();
    row.duration = duration;
    row.integrator = integrator;
    const auto t0 = std::chrono::steady_clock::now();

    // Keep the run at the smallest unstable dt seen (it says why the limit is where it is).
    double smallest_unstable = INFINITY;
    auto stable = [&](double dt) {
      if (row.interrupted) return false;
      ProbeSpec spec;
      spec.integrator = integrator;
      spec.dt = dt;
      spec.duration = duration;
      spec.energy_margin = options.energy_margin;
      spec.interrupted = options.interrupted;
      ProbeResult p = run_probe(base, spec);
      if (p.status == ProbeStatus::Interrupted) {
        row.interrupted = true;
        return false;
      }
      if (options.log) {
        *options.log << "stability: " << scene.name << ", " << integrator_name(integrator)
                     << ", dt " << sig(dt) << " s: " << failure_text(p) << "\n";
        options.log->flush();
      }
      if (!p.stable() && dt < smallest_unstable) {
        smallest_unstable = dt;
        row.failure = std::move(p);
        return false;
      }
      return p.stable();
    };
    BisectionOptions b;
    b.start = options.dt_start > 0.0 ? options.dt_start : options.dt_max;
    b.min = options.dt_min;
    b.max = options.dt_max;
    b.precision = options.precision;
    row.bisection = bisect_largest_stable(stable, b);
    row.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const bool interrupted = row.interrupted;
    rows.push_back(std::move(row));
    if (interrupted) break;
  }
  return rows;
}

std::string stability_limit_text(const StabilityRow& row) {
  if (row.interrupted) return "interrupted";
  if (row.bisection.stable_at_max) return ">= " + sig(row.bisection.largest_stable);
  if (row.bisection.unstable_at_min) return "< " + sig(row.bisection.smallest_unstable);
  return sig(row.bisection.largest_stable, 2);
}

std::string stability_csv(const std::vector<StabilityRow>& rows) {
  std::ostringstream out;
  out << "scene,integrator,vertices,triangles,duration_s,largest_stable_dt_s,"
         "smallest_unstable_dt_s,limit,trials,failure_status,failure_step,failure_vertex,"
         "failure_reason,search_seconds\n";
  for (const StabilityRow& r : rows) {
    std::string reason = r.failure.failure ? r.failure.failure->reason : "";
    std::replace(reason.begin(), reason.end(), '"', '\'');
    out << r.scene_name << "," << integrator_name(r.integrator) << "," << r.vertices << ","
        << r.triangles << "," << sig(r.duration, 6) << "," << sig(r.bisection.largest_stable, 4)
        << "," << sig(r.bisection.smallest_unstable, 4) << ",\"" << stability_limit_text(r)
        << "\"," << r.bisection.trials.size() << ",";
    if (r.bisection.smallest_unstable > 0.0 && r.failure.failure) {
      out << probe_status_name(r.failure.status) << "," << r.failure.failure->step << ","
          << r.failure.failure->vertex << ",\"" << reason << "\"";
    } else {
      out << ",,,";
    }
    out << "," << sig(r.seconds, 3) << "\n";
  }
  return out.str();
}

std::string stability_markdown(const std::vector<StabilityRow>& rows,
                               const StabilityOptions& options) {
  std::ostringstream md;
  md << "# Largest stable time step (s)\n\n";
  md << "Bisection to " << sig(100 * options.precision) << " % over each scene's full "
        "duration, between "
     << sig(options.dt_min) << " s and " << sig(options.dt_max)
     << " s. Stable: no non-finite value, no vertex faster than the scene's max_speed, total "
        "energy below start + "
     << sig(options.energy_margin) << " W (W: work gravity and external drivers can do), no "
        "vertex inside an obstacle. \">=\": stable at the largest step tried; \"<\": unstable "
        "at the smallest.\n\n";

  // Matrix: scenes down, integrators across (in the order first seen).
  std::vector<std::string> scenes;
  std::vector<Integrator> integrators;
  std::map<std::pair<std::string, Integrator>, const StabilityRow*> cell;
  for (const StabilityRow& r : rows) {
    if (std::find(scenes.begin(), scenes.end(), r.scene_name) == scenes.end()) {
      scenes.push_back(r.scene_name);
    }
    if (std::find(integrators.begin(), integrators.end(), r.integrator) == integrators.end()) {
      integrators.push_back(r.integrator);
    }
    cell[{r.scene_name, r.integrator}] = &r;
  }
  md << "| scene |";
  for (Integrator i : integrators) md << " " << integrator_name(i) << " |";
  md << "\n|---|";
  for (size_t k = 0; k < integrators.size(); ++k) md << "---:|";
  md << "\n";
  for (const std::string& s : scenes) {
    md << "| " << s << " |";
    for (Integrator i : integrators) {
      auto it = cell.find({s, i});
      md << " " << (it == cell.end() ? "" : stability_limit_text(*it->second)) << " |";
    }
    md << "\n";
  }

  md << "\n## What fails first, just above the limit\n\n";
  md << "| scene | integrator | vertices | duration (s) | unstable dt (s) | failure | trials | "
        "search time (s) |\n";
  md << "|---|---|---:|---:|---:|---|---:|---:|\n";
  for (const StabilityRow& r : rows) {
    md << "| " << r.scene_name << " | " << integrator_name(r.integrator) << " | " << r.vertices
       << " | " << sig(r.duration) << " | "
       << (r.bisection.smallest_unstable > 0 ? sig(r.bisection.smallest_unstable) : "-") << " | "
       << (r.bisection.smallest_unstable > 0 && r.failure.failure ? failure_text(r.failure)
                                                                  : "none")
       << " | " << r.bisection.trials.size() << " | " << sig(r.seconds, 3) << " |\n";
  }
  return md.str();
}

}  // namespace tissu
