#include "figure/paper_experiments.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <thread>

#include "core/error.h"
#include "figure/panel.h"
#include "physics/diagnostics.h"
#include "physics/stepper.h"
#include "render/renderer.h"
#include "core/utc_time.h"
#include "video/partial_file.h"

namespace tissu {

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

// ---------------------------------------------------------------------------------------
// Formatting

std::string fmt(const char* format, double value) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, value);
  return buf;
}

std::string num(double v) { return fmt("%.6g", v); }

// A CSV row: experiment, case, integrator, dt, stiffness scale, correction, quantity, value,
// unit, paper value.
struct CsvRow {
  std::string experiment, scene, integrator;
  double dt = 0, stiffness_scale = 1;
  std::string correction, quantity, value, unit, paper;
};

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string out = "\"";
  for (char c : s) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

class Table {
 public:
  explicit Table(std::vector<std::string> header) : header_(std::move(header)) {}
  void row(std::vector<std::string> cells) { rows_.push_back(std::move(cells)); }
  std::string markdown() const {
    std::string out = line(header_);
    std::string sep = "|";
    for (size_t i = 0; i < header_.size(); ++i) sep += " --- |";
    out += sep + "\n";
    for (const auto& r : rows_) out += line(r);
    return out + "\n";
  }

 private:
  static std::string line(const std::vector<std::string>& cells) {
    std::string out = "|";
    for (const std::string& c : cells) out += " " + c + " |";
    return out + "\n";
  }
  std::vector<std::string> header_;
  std::vector<std::vector<std::string>> rows_;
};

// ---------------------------------------------------------------------------------------
// Machine description

std::string cpu_field(const std::string& name) {
  std::ifstream in("/proc/cpuinfo");
  for (std::string line; std::getline(in, line);) {
    if (line.rfind(name, 0) == 0) {
      const size_t colon = line.find(':');
      if (colon != std::string::npos) {
        std::string v = line.substr(colon + 1);
        v.erase(0, v.find_first_not_of(" \t"));
        return v;
      }
    }
  }
  return "unknown";
}

int cpu_processors() {
  std::ifstream in("/proc/cpuinfo");
  int n = 0;
  for (std::string line; std::getline(in, line);) n += line.rfind("processor", 0) == 0;
  return n;
}

std::string command_output(const char* command) {
  std::string out;
  if (FILE* p = popen(command, "r")) {
    char buf[256];
    while (std::fgets(buf, sizeof buf, p)) out += buf;
    pclose(p);
  }
  while (!out.empty() && (out.back() == '\n' || out.back() == '\r')) out.pop_back();
  return out;
}

std::string load_average() {
  std::ifstream in("/proc/loadavg");
  double one = 0, five = 0, fifteen = 0;
  if (!(in >> one >> five >> fifteen)) return "unknown";
  return fmt("%.2f", one) + " / " + fmt("%.2f", five) + " / " + fmt("%.2f", fifteen);
}



// ---------------------------------------------------------------------------------------
// Running

const std::vector<Integrator> kPaperIntegrators = {Integrator::ExplicitEuler,
                                                   Integrator::SymplecticEuler,
                                                   Integrator::BenameurDjedi};

const char* paper_name(Integrator i) {
  switch (i) {
    case Integrator::ExplicitEuler: return "explicit Euler (eq. 9)";
    case Integrator::SymplecticEuler: return "modified Euler (eq. 10)";
    case Integrator::BenameurDjedi: return "paper's scheme, h F/(2m)";
    default: return integrator_name(i);
  }
}

struct Outcome {
  State state;  // the last good state
  std::optional<Divergence> divergence;
  double seconds = 0.0;  // wall time of the steps
};

// Steps a copy of `initial` `steps` times; `sample` sees iteration 0 and every `every`.
Outcome advance(const Model& model, const State& initial, long long steps, long long every = 0,
                const std::function<void(const State&)>& sample = {}) {
  Outcome out;
  State state = initial;
  Stepper stepper(model, state);
  if (sample) sample(state);
  while (state.step < steps) {
    out.divergence = stepper.advance(true);  // the last good state, should this step diverge
    if (out.divergence) {
      stepper.restore_before();
      break;
    }
    if (sample && every > 0 && state.step % every == 0) sample(state);
  }
  out.state = std::move(state);
  out.seconds = stepper.totals().wall_seconds;
  return out;
}

Vec3 centre_of_mass(const Model& model, const Vec3List& x) {
  Vec3 sum = Vec3::Zero();
  double m = 0.0;
  for (int i = 0; i < model.num_vertices(); ++i) {
    sum += model.mass[i] * x[i];
    m += model.mass[i];
  }
  return sum / m;
}

double rms_distance(const Vec3List& a, const Vec3List& b) {
  double s = 0.0;
  for (size_t i = 0; i < a.size(); ++i) s += (a[i] - b[i]).squaredNorm();
  return std::sqrt(s / static_cast<double>(a.size()));
}

double max_distance(const Vec3List& a, const Vec3List& b) {
  double m = 0.0;
  for (size_t i = 0; i < a.size(); ++i) m = std::max(m, (a[i] - b[i]).norm());
  return m;
}

double max_speed(const State& s) {
  double m = 0.0;
  for (const Vec3& v : s.v) m = std::max(m, v.norm());
  return m;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

void scale_stiffness(Material& m, double s) {
  m.weft *= s;
  m.warp *= s;
  m.coupling *= s;
  m.shear *= s;
}

std::string correction_text(const Model& m) {
  if (!m.position_correction) return "none";
  return "threshold " + num(m.position_correction->threshold) + " m, " +
         std::to_string(m.position_correction->iterations) + " iterations";
}

std::string divergence_cell(const Outcome& o) {
  return o.divergence ? std::to_string(o.divergence->step) : std::string("none");
}

struct Loaded {
  std::string file;
  Scene scene;
  Simulation sim;
};

Loaded load(const std::string& file, const std::vector<std::pair<std::string, Json>>& overrides = {}) {
  Json doc = read_scene_json(file);
  for (const auto& [k, v] : overrides) apply_panel_override(doc, k, v);
  Loaded l;
  l.file = file;
  try {
    l.scene = parse_scene(doc, file);
  } catch (const InputError& e) {
    throw InputError(file + ": " + e.what());
  }
  l.sim = build_simulation(l.scene);
  return l;
}

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

long long paper_divergence(Integrator i) {
  return i == Integrator::BenameurDjedi ? 115 : 32;
}

struct Report {
  std::string md;
  std::vector<CsvRow> csv;
  std::function<void(const std::string&)> log;
  void say(const std::string& s) const {
    if (log) log(s);
  }
};

// ---------------------------------------------------------------------------------------
// (a) Timing

void timing(const PaperOptions& o, Report& r, long long iterations) {
  r.md += "## (a) Time for " + std::to_string(iterations) + " iterations\n\n";
  r.md +=
      "Each piece runs its scene (`scenes/paper/tissu1.json`, `tissu2.json`, with their position "
      "correction) for " + std::to_string(iterations) +
      " iterations with each of the paper's three integrators. The simulation time is the wall "
      "time of the steps only (mesh generation and set-up excluded), on one thread; of " +
      std::to_string(o.repeats) +
      " runs, the fastest is the one least disturbed by the other processes on the machine "
      "and is used for the ratios, the median is shown beside it. Rendering is timed apart: 30 states taken evenly over the run are "
      "drawn off screen at 1280 x 720 (4x MSAA, the scenes' render settings) and read back; "
      "the renderer's set-up (context, shaders) is not included. The paper's times are those "
      "printed under its figures 1-3 (Intel Core i5 680, 3.6 GHz).\n\n";
  Table t({"piece", "triangles", "integrator", "paper T (s)", "our simulation T (s), fastest",
           "median / slowest (s)", "paper / ours", "ms per iteration", "state at the end",
           "rendering: ms per frame (30 frames, 1280x720)"});
  std::map<std::string, std::map<Integrator, double>> ours;
  for (const char* name : {"tissu1.json", "tissu2.json"}) {
    Loaded l = load((fs::path(o.scenes_dir) / name).string());
    const std::string piece = l.scene.name;
    for (Integrator integ : kPaperIntegrators) {
      Model model = l.sim.model;
      model.integrator = integ;
      std::vector<double> seconds;
      std::vector<State> frames;
      Outcome last;
      for (int rep = 0; rep < o.repeats; ++rep) {
        const long long every = std::max<long long>(1, iterations / 29);
        std::function<void(const State&)> sample;
        if (rep == 0) {
          sample = [&](const State& s) {
            if (frames.size() < 30) frames.push_back(s);
          };
        }
        last = advance(model, l.sim.state, iterations, every, sample);
        seconds.push_back(last.seconds);
      }
      // Rendering, timed apart.
      RenderSettings settings = panel_render_settings(l.scene, 1280, 720);
      Renderer renderer(settings);
      fit_panel_camera(renderer, model, l.sim.state.x);
      std::vector<uint8_t> rgb;
      const auto t0 = Clock::now();
      for (const State& s : frames) {
        renderer.draw(panel_frame_content(model, s));
        renderer.read_rgb(rgb);
      }
      const double render_s = std::chrono::duration<double>(Clock::now() - t0).count();
      const double render_ms = 1e3 * render_s / static_cast<double>(frames.size());

      const double med = median(seconds);
      const double mn = *std::min_element(seconds.begin(), seconds.end());
      const double mx = *std::max_element(seconds.begin(), seconds.end());
      ours[piece][integ] = mn;
      const double paper = paper_seconds(piece, integ);
      const std::string end = last.divergence
                                  ? "diverged at " + std::to_string(last.divergence->step)
                                  : "ran " + std::to_string(iterations) + ", max speed " +
                                        fmt("%.3g", max_speed(last.state)) + " m/s";
      t.row({piece, std::to_string(model.num_triangles()), paper_name(integ),
             fmt("%.3f", paper), fmt("%.3f", mn), fmt("%.3f", med) + " / " + fmt("%.3f", mx),
             fmt("%.0f", paper / (mn * 2000.0 / static_cast<double>(iterations))),
             fmt("%.4f", 1e3 * mn / iterations), end,
             fmt("%.1f", render_ms)});
      const std::string corr = correction_text(model);
      r.csv.push_back({"a_time", piece, integrator_name(integ), model.dt, 1, corr,
                       "simulation_wall_time_fastest", num(mn), "s", num(paper)});
      r.csv.push_back({"a_time", piece, integrator_name(integ), model.dt, 1, corr,
                       "simulation_wall_time_median", num(med), "s", ""});
      r.csv.push_back({"a_time", piece, integrator_name(integ), model.dt, 1, corr,
                       "ms_per_iteration", num(1e3 * mn / iterations), "ms", num(1e3 * paper / 2000)});
      r.csv.push_back({"a_time", piece, integrator_name(integ), model.dt, 1, corr,
                       "render_ms_per_frame_1280x720", num(render_ms), "ms", ""});
      r.csv.push_back({"a_time", piece, integrator_name(integ), model.dt, 1, corr,
                       "iterations_run", std::to_string(last.state.step), "", "2000"});
      r.say("(a) " + piece + ", " + integrator_name(integ) + ": " + fmt("%.3f s", mn));
    }
  }
  r.md += t.markdown();
  if (ours.count("Tissu 1") && ours.count("Tissu 2")) {
    Table s({"integrator", "paper: T(Tissu 1) / T(Tissu 2)", "ours (fastest runs)"});
    for (Integrator integ : kPaperIntegrators) {
      s.row({paper_name(integ),
             fmt("%.2f", paper_seconds("Tissu 1", integ) / paper_seconds("Tissu 2", integ)),
             fmt("%.2f", ours["Tissu 1"][integ] / ours["Tissu 2"][integ])});
    }
    r.md += "Growth of the time with the mesh (4847 / 961 = " + fmt("%.2f", 4847.0 / 961.0) +
            " times the triangles):\n\n" + s.markdown();
  }
}

// ---------------------------------------------------------------------------------------
// (b) Divergence

void divergence(const PaperOptions& o, Report& r, long long iterations) {
  const std::string file = (fs::path(o.scenes_dir) / "piece990.json").string();
  Loaded l = load(file);
  const Model base = l.sim.model;
  const double dt0 = base.dt;
  r.md += "## (b) Divergence without position correction\n\n";
  r.md += "The 990-triangle piece (`scenes/paper/piece990.json`: " +
          std::to_string(base.num_triangles()) + " triangles, " + base.material.name +
          ", dt = " + num(dt0) + " s) runs up to " + std::to_string(iterations) +
          " iterations. A run diverges at the first iteration that leaves a non-finite value or "
          "a vertex faster than " + num(base.max_speed) +
          " m/s. \"With correction\" uses the scene's position correction (" +
          correction_text(base) + ").\n\n";
  Table t({"integrator", "paper: diverges after", "ours without correction: diverges at",
           "why", "with correction: iterations run", "max speed at the end (m/s)",
           "largest strain at the end"});
  for (Integrator integ : kPaperIntegrators) {
    Model without = base;
    without.integrator = integ;
    without.position_correction.reset();
    const Outcome a = advance(without, l.sim.state, iterations);
    Model with = base;
    with.integrator = integ;
    const Outcome b = advance(with, l.sim.state, iterations);
    const FrameStats stats = measure_frame(with, b.state);
    t.row({paper_name(integ), std::to_string(paper_divergence(integ)), divergence_cell(a),
           a.divergence ? a.divergence->reason : "-",
           b.divergence ? "diverged at " + std::to_string(b.divergence->step)
                        : std::to_string(b.state.step),
           fmt("%.3g", stats.max_speed), fmt("%.3g", stats.max_strain)});
    r.csv.push_back({"b_divergence", l.scene.name, integrator_name(integ), dt0, 1, "none",
                     "divergence_iteration", divergence_cell(a), "iteration",
                     std::to_string(paper_divergence(integ))});
    r.csv.push_back({"b_divergence", l.scene.name, integrator_name(integ), dt0, 1,
                     correction_text(with), "iterations_run", std::to_string(b.state.step),
                     "iteration", "2000"});
    r.csv.push_back({"b_divergence", l.scene.name, integrator_name(integ), dt0, 1,
                     correction_text(with), "max_speed_end", num(stats.max_speed), "m/s", ""});
    r.say("(b) " + std::string(integrator_name(integ)) + ": without correction " +
          divergence_cell(a));
  }
  r.md += t.markdown();

  // Time step x stiffness.
  const std::vector<double> dts = o.quick ? std::vector<double>{1e-4, 1.3e-4}
                                          : std::vector<double>{5e-5, 7.5e-5, 1e-4, 1.15e-4,
                                                                1.3e-4, 1.5e-4, 2e-4};
  const std::vector<double> scales =
      o.quick ? std::vector<double>{0.5, 1} : std::vector<double>{0.25, 0.5, 1, 2, 4};
  r.md += "### Where the divergence point moves with the time step and the stiffness\n\n";
  r.md += "Iteration of divergence without position correction (\"none\": ran " +
          std::to_string(iterations) +
          " iterations). The stiffness scale multiplies the four membrane stiffnesses of the "
          "material (weft, warp, coupling, shear); 1 is the " + base.material.name +
          " preset. Explicit integrators are stable below a step proportional to "
          "1/sqrt(stiffness), so the boundary should depend on dt x sqrt(scale) only; the "
          "last lines of each table give the measured boundary in that variable.\n\n";
  for (Integrator integ : kPaperIntegrators) {
    std::vector<std::string> header = {"dt (s) \\ stiffness scale"};
    for (double s : scales) header.push_back(num(s));
    Table t2(header);
    double largest_stable = 0, smallest_diverging = 1e300;
    for (double dt : dts) {
      std::vector<std::string> row = {num(dt)};
      for (double s : scales) {
        Model m = base;
        m.integrator = integ;
        m.dt = dt;
        m.position_correction.reset();
        scale_stiffness(m.material, s);
        const Outcome out = advance(m, l.sim.state, iterations);
        row.push_back(divergence_cell(out));
        const double x = dt * std::sqrt(s);
        if (out.divergence) smallest_diverging = std::min(smallest_diverging, x);
        else largest_stable = std::max(largest_stable, x);
        r.csv.push_back({"b_divergence_table", l.scene.name, integrator_name(integ), dt, s, "none",
                         "divergence_iteration", divergence_cell(out), "iteration", ""});
      }
      t2.row(row);
    }
    r.md += "**" + std::string(paper_name(integ)) + "**\n\n" + t2.markdown();
    r.md += "Largest dt x sqrt(scale) that ran " + std::to_string(iterations) + " iterations: " +
            (largest_stable > 0 ? num(largest_stable) + " s" : std::string("none")) +
            "; smallest that diverged: " +
            (smallest_diverging < 1e300 ? num(smallest_diverging) + " s" : std::string("none")) +
            ".\n\n";
    r.csv.push_back({"b_divergence_boundary", l.scene.name, integrator_name(integ), 0, 0, "none",
                     "largest_stable_dt_sqrt_scale", num(largest_stable), "s", ""});
    r.csv.push_back({"b_divergence_boundary", l.scene.name, integrator_name(integ), 0, 0, "none",
                     "smallest_diverging_dt_sqrt_scale",
                     smallest_diverging < 1e300 ? num(smallest_diverging) : "", "s", ""});
    r.say("(b) table done: " + std::string(integrator_name(integ)));
  }

  // Correction settings.
  const std::vector<double> caps = o.quick ? std::vector<double>{4} : std::vector<double>{1, 2, 4, 8, 16};
  const std::vector<int> its = o.quick ? std::vector<int>{1, 4} : std::vector<int>{1, 2, 4, 8};
  r.md += "### Position correction settings\n\n";
  r.md += "The correction halves a vertex's step displacement (up to n_it times) while it is "
          "longer than the threshold, so a vertex moving faster than threshold / dt is slowed: "
          "the threshold is best given as a speed cap v_cap = threshold / dt above the speeds "
          "of the real motion. Each cell: iterations run (of " + std::to_string(iterations) +
          ") and, after a slash, the largest vertex speed at the end (m/s), at dt = " +
          num(dt0) + " s.\n\n";
  for (Integrator integ : kPaperIntegrators) {
    std::vector<std::string> header = {"v_cap (m/s) \\ n_it"};
    for (int n : its) header.push_back(std::to_string(n));
    Table t3(header);
    for (double cap : caps) {
      std::vector<std::string> row = {num(cap) + " (threshold " + num(cap * dt0) + " m)"};
      for (int n : its) {
        Model m = base;
        m.integrator = integ;
        m.position_correction = PositionCorrection{cap * dt0, n};
        const Outcome out = advance(m, l.sim.state, iterations);
        row.push_back(out.divergence ? "diverged at " + std::to_string(out.divergence->step)
                                     : std::to_string(out.state.step) + " / " +
                                           fmt("%.3g", max_speed(out.state)));
        r.csv.push_back({"b_correction_table", l.scene.name, integrator_name(integ), dt0, 1,
                         correction_text(m), "iterations_run",
                         std::to_string(out.divergence ? out.divergence->step : out.state.step),
                         "iteration", ""});
      }
      t3.row(row);
    }
    r.md += "**" + std::string(paper_name(integ)) + "**\n\n" + t3.markdown();
  }
}

// ---------------------------------------------------------------------------------------
// (c) Accuracy

void accuracy(const PaperOptions& o, Report& r, long long iterations) {
  const std::string file = (fs::path(o.scenes_dir) / "piece990.json").string();
  Loaded l = load(file);
  const Model base = l.sim.model;
  const double dt0 = base.dt;
  const double T = static_cast<double>(iterations) * dt0;
  const int finest = o.quick ? 4 : 6;  // reference step dt / 2^finest
  r.md += "## (c) Distance from a converged reference\n\n";
  r.md += "The reference is the 990-triangle piece run with modified (symplectic) Euler "
          "without position correction at dt / 2^k, to the same time T = " +
          std::to_string(iterations) + " x " + num(dt0) + " s = " + num(T) +
          " s. Distances are root-mean-square (and largest) over the vertices of the position "
          "differences at T.\n\n";
  std::map<int, State> ref;
  Table conv({"k", "step (s)", "iterations", "RMS distance to k + 1 (mm)", "ratio to the previous"});
  for (int k = 3; k <= finest; ++k) {
    Model m = base;
    m.integrator = Integrator::SymplecticEuler;
    m.position_correction.reset();
    m.dt = dt0 / std::pow(2.0, k);
    const long long n = iterations << k;
    const Outcome out = advance(m, l.sim.state, n);
    if (out.divergence) {
      throw OutputError("paper experiments: the reference run at dt = " + num(m.dt) +
                        " s diverged at iteration " + std::to_string(out.divergence->step));
    }
    ref[k] = out.state;
    r.say("(c) reference k = " + std::to_string(k) + " done");
  }
  double previous = 0.0;
  for (int k = 3; k < finest; ++k) {
    const double d = rms_distance(ref[k].x, ref[k + 1].x);
    conv.row({std::to_string(k), num(dt0 / std::pow(2.0, k)), std::to_string(iterations << k),
              fmt("%.4g", 1e3 * d), previous > 0 ? fmt("%.2f", previous / d) : "-"});
    r.csv.push_back({"c_reference_convergence", l.scene.name, "symplectic_euler",
                     dt0 / std::pow(2.0, k), 1, "none", "rms_distance_to_half_step", num(d), "m", ""});
    previous = d;
  }
  r.md += "Convergence of the reference (first order: each halving should halve the "
          "difference, ratio 2):\n\n" + conv.markdown();
  const State& reference = ref[finest];
  const Vec3 ref_com = centre_of_mass(base, reference.x);
  const Vec3 start_com = centre_of_mass(base, l.sim.state.x);
  const double ref_drop = start_com.z() - ref_com.z();
  r.md += "Reference: k = " + std::to_string(finest) + " (dt = " + num(dt0 / std::pow(2.0, finest)) +
          " s); its own error is about the last difference above. Its centre of mass has dropped "
          "by " + fmt("%.2f", 1e3 * ref_drop) + " mm at T.\n\n";

  Table t({"integrator", "step (s)", "position correction", "iterations",
           "RMS distance (mm)", "largest distance (mm)", "centre-of-mass drop (mm)",
           "drop / reference drop"});
  auto add = [&](Integrator integ, int k, bool correction) {
    Model m = base;
    m.integrator = integ;
    if (!correction) m.position_correction.reset();
    m.dt = dt0 / std::pow(2.0, k);
    const long long n = iterations << k;
    const Outcome out = advance(m, l.sim.state, n);
    const std::string corr = correction ? "yes" : "no";
    if (out.divergence) {
      t.row({paper_name(integ), num(m.dt), corr, "diverged at " + std::to_string(out.divergence->step),
             "-", "-", "-", "-"});
      r.csv.push_back({"c_accuracy", l.scene.name, integrator_name(integ), m.dt, 1,
                       correction_text(m), "divergence_iteration",
                       std::to_string(out.divergence->step), "iteration", ""});
      return;
    }
    const double rms = rms_distance(out.state.x, reference.x);
    const double mx = max_distance(out.state.x, reference.x);
    const double drop = start_com.z() - centre_of_mass(base, out.state.x).z();
    t.row({paper_name(integ), num(m.dt), corr, std::to_string(n), fmt("%.3g", 1e3 * rms),
           fmt("%.3g", 1e3 * mx), fmt("%.2f", 1e3 * drop), fmt("%.3f", drop / ref_drop)});
    r.csv.push_back({"c_accuracy", l.scene.name, integrator_name(integ), m.dt, 1,
                     correction_text(m), "rms_distance_to_reference", num(rms), "m", ""});
    r.csv.push_back({"c_accuracy", l.scene.name, integrator_name(integ), m.dt, 1,
                     correction_text(m), "max_distance_to_reference", num(mx), "m", ""});
    r.csv.push_back({"c_accuracy", l.scene.name, integrator_name(integ), m.dt, 1,
                     correction_text(m), "com_drop_over_reference", num(drop / ref_drop), "", ""});
  };
  for (Integrator integ : kPaperIntegrators) {
    add(integ, 0, true);
    add(integ, 0, false);
    for (int k = 3; k <= (o.quick ? 3 : 5); ++k) add(integ, k, false);
    r.say("(c) " + std::string(integrator_name(integ)) + " done");
  }
  r.md += "Each integrator at the figures' step (with and without correction) and at smaller "
          "steps without correction:\n\n" + t.markdown();

  // Free fall: no pins, no air, no obstacles; the exact discrete answers.
  Loaded ff = load(file, {{"cloth.pins", Json()}, {"air_damping", Json()}});
  const double g = 9.81;
  const double vcap = ff.sim.model.position_correction
                          ? ff.sim.model.position_correction->threshold / dt0
                          : 0.0;
  r.md += "### Free fall: the paper's h F / (2 m) halves gravity\n\n";
  r.md += "The same piece without its pins and without air friction falls freely to T = " +
          num(T) + " s, with the scene's position correction (speed cap threshold / dt = " +
          (vcap > 0 ? num(vcap) + " m/s at every step: the threshold is scaled with dt"
                   : std::string("none")) +
          ", above the speed reached, g T = " + fmt("%.3g", g * T) +
          " m/s). A rigid translation has no elastic force, so an integrator that stays stable "
          "follows its exact discrete formula (h the step, n the iterations); an unstable one "
          "amplifies the round-off in the elastic forces until it shows. Continuous free fall: "
          "g T^2 / 2 = " + fmt("%.4f", 1e3 * 0.5 * g * T * T) + " mm.\n\n";
  Table f({"integrator", "step (s)", "iterations", "formula for the drop", "formula (mm)",
           "measured drop (mm)", "relative difference", "drop / (g T^2 / 2)"});
  for (Integrator integ : kPaperIntegrators) {
    for (int k : {0, 3}) {
      Model m = ff.sim.model;
      m.integrator = integ;
      m.dt = dt0 / std::pow(2.0, k);
      // Same speed cap threshold / dt at every step.
      if (m.position_correction) m.position_correction->threshold /= std::pow(2.0, k);
      const long long steps = iterations << k;
      const Outcome out = advance(m, ff.sim.state, steps);
      const double n = static_cast<double>(steps), h = m.dt;
      double formula = 0;
      std::string text;
      switch (integ) {
        case Integrator::ExplicitEuler: formula = g * h * h * n * (n - 1) / 2; text = "g h^2 n(n-1)/2"; break;
        case Integrator::SymplecticEuler: formula = g * h * h * n * (n + 1) / 2; text = "g h^2 n(n+1)/2"; break;
        default: formula = g * h * h * n * (n + 1) / 4; text = "g h^2 n(n+1)/4"; break;
      }
      if (out.divergence) {
        f.row({paper_name(integ), num(h), "diverged at " + std::to_string(out.divergence->step),
               text, fmt("%.4f", 1e3 * formula), "-", "-", "-"});
        continue;
      }
      const double drop =
          centre_of_mass(m, ff.sim.state.x).z() - centre_of_mass(m, out.state.x).z();
      f.row({paper_name(integ), num(h), std::to_string(steps), text, fmt("%.4f", 1e3 * formula),
             fmt("%.4f", 1e3 * drop), fmt("%.1e", (drop - formula) / formula),
             fmt("%.4f", drop / (0.5 * g * T * T))});
      r.csv.push_back({"c_free_fall", ff.scene.name, integrator_name(integ), h, 1,
                       correction_text(m), "com_drop", num(drop), "m", ""});
      r.csv.push_back({"c_free_fall", ff.scene.name, integrator_name(integ), h, 1,
                       correction_text(m), "com_drop_formula", num(formula), "m", ""});
    }
  }
  r.md += f.markdown();
}

// ---------------------------------------------------------------------------------------
// (d) Figure 11

void hung(const PaperOptions& o, Report& r) {
  Loaded l = load((fs::path(o.scenes_dir) / "hung3.json").string());
  const long long steps = o.quick ? 2000 : l.scene.steps;
  r.md += "## (d) The cloth hung at 3 points (figure 11)\n\n";
  r.md += "`scenes/paper/hung3.json` (" + std::to_string(l.sim.model.num_triangles()) +
          " triangles, " + correction_text(l.sim.model) + ") run for " + std::to_string(steps) +
          " iterations (" + fmt("%.3f", steps * l.sim.model.dt) + " s). Kinetic energy and speeds at the "
          "end tell whether it came to rest.\n\n";
  Table t({"integrator", "position correction", "status", "kinetic energy (J)",
           "largest speed (m/s)", "RMS speed (m/s)", "largest strain"});
  for (Integrator integ : kPaperIntegrators) {
    for (bool correction : {true, false}) {
      Model m = l.sim.model;
      m.integrator = integ;
      if (!correction) m.position_correction.reset();
      const Outcome out = advance(m, l.sim.state, steps);
      const FrameStats s = measure_frame(m, out.state);
      double v2 = 0;
      for (const Vec3& v : out.state.v) v2 += v.squaredNorm();
      const double rms_v = std::sqrt(v2 / static_cast<double>(out.state.v.size()));
      t.row({paper_name(integ), correction ? "yes" : "no",
             out.divergence ? "diverged at " + std::to_string(out.divergence->step)
                            : "ran " + std::to_string(out.state.step),
             out.divergence ? "-" : fmt("%.3g", s.kinetic_energy),
             out.divergence ? "-" : fmt("%.3g", s.max_speed),
             out.divergence ? "-" : fmt("%.3g", rms_v),
             out.divergence ? "-" : fmt("%.3g", s.max_strain)});
      r.csv.push_back({"d_hung3", l.scene.name, integrator_name(integ), m.dt, 1,
                       correction_text(m), out.divergence ? "divergence_iteration" : "kinetic_energy_end",
                       out.divergence ? std::to_string(out.divergence->step) : num(s.kinetic_energy),
                       out.divergence ? "iteration" : "J", ""});
      if (!out.divergence) {
        r.csv.push_back({"d_hung3", l.scene.name, integrator_name(integ), m.dt, 1,
                         correction_text(m), "max_speed_end", num(s.max_speed), "m/s", ""});
      }
    }
    r.say("(d) " + std::string(integrator_name(integ)) + " done");
  }
  r.md += t.markdown();
}

}  // namespace

std::vector<std::string> paper_experiment_names() {
  return {"timing", "divergence", "accuracy", "hung"};
}

std::pair<std::string, std::string> run_paper_experiments(const PaperOptions& o) {
  for (const std::string& name : o.experiments) {
    const std::vector<std::string> names = paper_experiment_names();
    if (std::find(names.begin(), names.end(), name) == names.end()) {
      throw InputError("paper experiments: unknown experiment \"" + name +
                       "\" (timing, divergence, accuracy, hung)");
    }
  }
  const long long iterations = o.quick ? 200 : 2000;
  for (const char* f : {"tissu1.json", "tissu2.json", "piece990.json", "hung3.json"}) {
    const fs::path p = fs::path(o.scenes_dir) / f;
    std::error_code ec;
    if (!fs::is_regular_file(p, ec)) throw InputError(p.string() + ": scene file not found");
  }
  Report r;
  r.log = o.log;
  const auto start = Clock::now();
  r.md += "# Paper experiments: measured results\n\n";
  r.md += "Generated by `" + (o.command_line.empty() ? std::string("tissu paper") : o.command_line) +
          "` on " + utc_now("%Y-%m-%d %H:%M UTC") +
          (o.quick ? " in **quick mode** (fewer iterations and cells: a check of the command, "
                     "not results)"
                   : "") +
          ". Do not edit: run the command again. Every number below was measured by that run "
          "(except the paper's, quoted from its section 4); [paper.md](paper.md) explains the "
          "scenes, the choices and the reading. The same numbers are in "
          "[paper-results.csv](paper-results.csv).\n\n";
  const std::string commit = command_output("git rev-parse --short HEAD 2>/dev/null");
  const std::string dirty = command_output("git status --porcelain --untracked-files=no 2>/dev/null");
  r.md += "Machine: " + cpu_field("model name") + ", " + std::to_string(cpu_processors()) +
          " logical processors in /proc/cpuinfo (`cpu cores`: " + cpu_field("cpu cores") +
          "), " + std::to_string(std::thread::hardware_concurrency()) +
          " available to this process; the simulation runs on one thread. Compiler: " +
          std::string(__VERSION__) +
#ifdef NDEBUG
          ", optimised build" +
#else
          ", **debug build (times not representative)**" +
#endif
          (commit.empty() ? std::string() : ". Source: git " + commit + (dirty.empty() ? "" : " with local changes")) +
          ". Load average (1 / 5 / 15 min) at the start: " + load_average() +
          " (other processes share the machine: wall times above the single-run minimum "
          "reflect them).\nThe paper's machine: Intel Core i5 680 @ 3.60 GHz, 4 GB RAM.\n\n";

  auto chosen = [&](const char* name) {
    return o.experiments.empty() ||
           std::find(o.experiments.begin(), o.experiments.end(), name) != o.experiments.end();
  };
  if (chosen("timing")) timing(o, r, iterations);
  if (chosen("divergence")) divergence(o, r, iterations);
  if (chosen("accuracy")) accuracy(o, r, iterations);
  if (chosen("hung")) hung(o, r);
  r.md += "Load average at the end: " + load_average() + ". All experiments took " +
          fmt("%.0f", std::chrono::duration<double>(Clock::now() - start).count()) +
          " s of wall time.\n";

  std::string csv = "experiment,scene,integrator,dt_s,stiffness_scale,position_correction,quantity,value,unit,paper_value\n";
  for (const CsvRow& c : r.csv) {
    csv += csv_field(c.experiment) + "," + csv_field(c.scene) + "," + csv_field(c.integrator) + "," +
           (c.dt > 0 ? num(c.dt) : "") + "," + (c.stiffness_scale > 0 ? num(c.stiffness_scale) : "") +
           "," + csv_field(c.correction) + "," + csv_field(c.quantity) + "," + csv_field(c.value) +
           "," + csv_field(c.unit) + "," + csv_field(c.paper) + "\n";
  }
  std::error_code ec;
  fs::create_directories(o.out_dir, ec);
  const std::string md_path = (fs::path(o.out_dir) / "paper-results.md").string();
  const std::string csv_path = (fs::path(o.out_dir) / "paper-results.csv").string();
  write_text_file(md_path, r.md);
  write_text_file(csv_path, csv);
  return {md_path, csv_path};
}

}  // namespace tissu
