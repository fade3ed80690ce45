// (a) Time for the iterations on Tissu 1 and Tissu 2, next to the paper's times.
#include <algorithm>
#include <filesystem>
#include <map>

#include "core/cpu_clock.h"
#include "figure/panel.h"
#include "study/metrics.h"
#include "study/output.h"
#include "study/paper/experiments.h"
#include "study/paper/paper_runs.h"
#include "view/drawn_frame.h"
#include "view/scene_render_settings.h"

namespace tissu {

namespace {

namespace fs = std::filesystem;

// The paper's times (figure captions 1-3), s.
double paper_seconds(const std::string& piece, Integrator i) {
  const bool one = piece == "Tissu 1";
  switch (i) {
    case Integrator::ExplicitEuler: return one ? 58.020 : 11.710;
    case Integrator::SymplecticEuler: return one ? 57.460 : 11.990;
    case Integrator::BenameurDjedi: return one ? 58.715 : 12.144;
    default: return 0.0;
  }
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// Draws `frames` off screen at 1280 x 720 with the scene's settings; ms per frame.
double render_ms_per_frame(const PaperScene& l, const Model& model,
                           const std::vector<State>& frames) {
  Renderer renderer(still_render_settings(l.scene, 1280, 720));
  fit_panel_camera(renderer, model, l.sim.state.x);
  const double edge_length = mean_edge_length(model, l.sim.state.x);
  std::vector<uint8_t> rgb;
  const double t0 = wall_seconds();
  for (const State& s : frames) {
    renderer.draw(drawn_frame(model, s, edge_length));
    renderer.read_rgb(rgb);
  }
  return 1e3 * (wall_seconds() - t0) / static_cast<double>(frames.size());
}

const char* kIntroduction =
    " iterations with each of the paper's three integrators. The simulation time is the wall "
    "time of the steps only (mesh generation and set-up excluded), on one thread; of ";
const char* kMethod =
    " runs, the fastest is the one least disturbed by the other processes on the machine "
    "and is used for the ratios, the median is shown beside it. Rendering is timed apart: 30 "
    "states taken evenly over the run are drawn off screen at 1280 x 720 (4x MSAA, the scenes' "
    "render settings) and read back; the renderer's set-up (context, shaders) is not included. "
    "The paper's times are those printed under its figures 1-3 (Intel Core i5 680, 3.6 GHz).\n\n";

}  // namespace

void paper_timing(const PaperOptions& o, PaperReport& r, long long iterations) {
  r.md += "## (a) Time for " + std::to_string(iterations) + " iterations\n\n";
  r.md += "Each piece runs its scene (`scenes/paper/tissu1.json`, `tissu2.json`, with their "
          "position correction) for " + std::to_string(iterations) + kIntroduction +
          std::to_string(o.repeats) + kMethod;
  MarkdownTable t({"piece", "triangles", "integrator", "paper T (s)",
                   "our simulation T (s), fastest", "median / slowest (s)", "paper / ours",
                   "ms per iteration", "state at the end",
                   "rendering: ms per frame (30 frames, 1280x720)"});
  std::map<std::string, std::map<Integrator, double>> ours;
  for (const char* name : {"tissu1.json", "tissu2.json"}) {
    const PaperScene l = load_paper_scene((fs::path(o.scenes_dir) / name).string());
    const std::string piece = l.scene.name;
    for (Integrator integ : kPaperIntegrators) {
      Model model = l.sim.model;
      model.integrator = integ;
      // Timed runs; the first also keeps 30 states evenly over the run for drawing.
      std::vector<double> seconds;
      std::vector<State> frames;
      const long long every = std::max<long long>(1, iterations / 29);
      const auto keep_frame = [&](const State& s) {
        if (s.step % every == 0 && frames.size() < 30) frames.push_back(s);
      };
      PaperRun last;
      for (int rep = 0; rep < o.repeats; ++rep) {
        last = run_paper_case(model, l.sim.state, iterations,
                              rep == 0 ? std::function<void(const State&)>(keep_frame) : nullptr);
        seconds.push_back(last.seconds);
      }
      const double render_ms = render_ms_per_frame(l, model, frames);

      const double med = median(seconds);
      const double mn = *std::min_element(seconds.begin(), seconds.end());
      const double mx = *std::max_element(seconds.begin(), seconds.end());
      ours[piece][integ] = mn;
      const double paper = paper_seconds(piece, integ);
      const std::string end =
          last.divergence ? "diverged at " + std::to_string(last.divergence->step)
                          : "ran " + std::to_string(iterations) + ", max speed " +
                                sig(max_speed(last.state.v)) + " m/s";
      t.row({piece, std::to_string(model.num_triangles()), paper_name(integ),
             printf_text("%.3f", paper), printf_text("%.3f", mn),
             printf_text("%.3f", med) + " / " + printf_text("%.3f", mx),
             printf_text("%.0f", paper / (mn * 2000.0 / static_cast<double>(iterations))),
             printf_text("%.4f", 1e3 * mn / iterations), end, printf_text("%.1f", render_ms)});
      const auto row = [&](const std::string& quantity, const std::string& value,
                           const std::string& unit, const std::string& paper_value) {
        r.csv.push_back({"a_time", piece, integrator_name(integ), model.dt, 1,
                         correction_text(model), quantity, value, unit, paper_value});
      };
      row("simulation_wall_time_fastest", sig(mn, 6), "s", sig(paper, 6));
      row("simulation_wall_time_median", sig(med, 6), "s", "");
      row("ms_per_iteration", sig(1e3 * mn / iterations, 6), "ms", sig(1e3 * paper / 2000, 6));
      row("render_ms_per_frame_1280x720", sig(render_ms, 6), "ms", "");
      row("iterations_run", std::to_string(last.state.step), "", "2000");
      r.say("(a) " + piece + ", " + integrator_name(integ) + ": " + printf_text("%.3f s", mn));
    }
  }
  r.md += t.text();
  if (ours.count("Tissu 1") && ours.count("Tissu 2")) {
    MarkdownTable s({"integrator", "paper: T(Tissu 1) / T(Tissu 2)", "ours (fastest runs)"});
    for (Integrator integ : kPaperIntegrators) {
      s.row({paper_name(integ),
             printf_text("%.2f", paper_seconds("Tissu 1", integ) / paper_seconds("Tissu 2", integ)),
             printf_text("%.2f", ours["Tissu 1"][integ] / ours["Tissu 2"][integ])});
    }
    r.md += "Growth of the time with the mesh (4847 / 961 = " + printf_text("%.2f", 4847.0 / 961.0) +
            " times the triangles):\n\n" + s.text();
  }
}

}  // namespace tissu
