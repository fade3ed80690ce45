// How well an integrator drapes a scene, against a converged reference run of the same
// scene, and what each step costs (processor time, one thread):
//   ./build/bench/tissu_drape_bench SCENE [--set KEY=VALUE]... [--reference INTEGRATOR:DT]
//       [--cache FILE] [--fps F] VARIANT...
// A VARIANT is INTEGRATOR:DT[:KEY=VALUE,...] (the extra keys are scene overrides, e.g.
// backward_euler:0.0166667:implicit.cg_tolerance=1e-2). The reference defaults to
// symplectic_euler at the scene's own dt if the scene is explicit; an implicit scene needs
// --reference (the demo: symplectic_euler:4e-5). --cache keeps its frames in a file.
// Per variant it prints the status, ms per step, the RMS over the frames of the gap between
// the cloth's centroid heights (cm), and at the last frame the share of triangles
// compressed below 80% of their rest area, the mean angle between the normals of
// neighbouring triangles and the cloth's footprint (the area of its shadow on the x-y
// plane, m^2: a sheet that hangs close around an obstacle against one that stands out
// from it like a tent), with the reference's beside them.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "physics/cusick.h"
#include "physics/diagnostics.h"
#include "physics/step.h"
#include "scene/scene.h"

using namespace tissu;

namespace {

struct Frames {
  std::vector<Vec3List> x;  // positions at each frame time k / fps
};

struct Run {
  Frames frames;
  std::string status = "ok";
  double ms_per_step = 0.0;  // processor time, ms
  long long steps = 0;
  double max_energy_gain = 0.0;  // J, largest rise of the total energy over its start value
};

Run simulate(const std::string& scene_file, std::vector<std::string> overrides,
             const std::string& integrator, double dt, double fps) {
  overrides.push_back("integrator=\"" + integrator + "\"");
  std::ostringstream dt_text;
  dt_text.precision(17);
  dt_text << dt;
  overrides.push_back("dt=" + dt_text.str());
  const Scene scene = load_scene(scene_file, overrides);
  Simulation sim = build_simulation(scene);
  Workspace ws;
  ws.threads = 1;
  Run run;
  const double e0 = total_energy(sim.model, sim.state);
  const double duration = scene.steps * scene.dt;
  const long long frames = static_cast<long long>(std::floor(duration * fps + 1e-9)) + 1;
  run.frames.x.push_back(sim.state.x);
  double cpu = 0.0;
  for (long long k = 1; k < frames; ++k) {
    const double t_frame = k / fps;
    while (sim.state.t < t_frame - 1e-9 * dt) {
      const std::clock_t t0 = std::clock();
      const auto divergence = step(sim.model, sim.state, ws);
      cpu += static_cast<double>(std::clock() - t0) / CLOCKS_PER_SEC;
      run.steps += 1;
      if (divergence) {
        run.status = "diverged at t = " + std::to_string(divergence->time) + " s: " +
                     divergence->reason;
        run.ms_per_step = 1e3 * cpu / run.steps;
        return run;
      }
    }
    run.frames.x.push_back(sim.state.x);
    run.max_energy_gain = std::max(run.max_energy_gain, total_energy(sim.model, sim.state) - e0);
  }
  run.ms_per_step = 1e3 * cpu / std::max<long long>(1, run.steps);
  return run;
}

void save(const Frames& f, const std::string& path) {
  std::ofstream out(path, std::ios::binary);
  const uint64_t frames = f.x.size(), vertices = f.x.empty() ? 0 : f.x[0].size();
  out.write(reinterpret_cast<const char*>(&frames), sizeof frames);
  out.write(reinterpret_cast<const char*>(&vertices), sizeof vertices);
  for (const Vec3List& x : f.x) {
    out.write(reinterpret_cast<const char*>(x.data()), sizeof(Vec3) * vertices);
  }
}

bool load(Frames& f, const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  uint64_t frames = 0, vertices = 0;
  if (!in.read(reinterpret_cast<char*>(&frames), sizeof frames)) return false;
  in.read(reinterpret_cast<char*>(&vertices), sizeof vertices);
  f.x.assign(frames, Vec3List(vertices));
  for (Vec3List& x : f.x) in.read(reinterpret_cast<char*>(x.data()), sizeof(Vec3) * vertices);
  return static_cast<bool>(in);
}

double centroid_z(const Vec3List& x) {
  double z = 0.0;
  for (const Vec3& p : x) z += p.z();
  return z / x.size();
}

// Share of triangles whose area is below 80% of the rest area, %.
double compressed_share(const Model& m, const Vec3List& x) {
  int count = 0;
  for (int t = 0; t < m.num_triangles(); ++t) {
    const Tri& tri = m.triangles[t];
    const double area = 0.5 * (x[tri[1]] - x[tri[0]]).cross(x[tri[2]] - x[tri[0]]).norm();
    if (area < 0.8 * m.rest[t].area) ++count;
  }
  return 100.0 * count / m.num_triangles();
}

// Mean angle between the unit normals of triangles sharing an edge, degrees.
double mean_normal_angle(const Model& m, const Vec3List& x) {
  std::map<std::pair<int, int>, int> first_of_edge;
  double sum = 0.0;
  int pairs = 0;
  std::vector<Vec3> normal(m.num_triangles());
  for (int t = 0; t < m.num_triangles(); ++t) {
    const Tri& tri = m.triangles[t];
    normal[t] = (x[tri[1]] - x[tri[0]]).cross(x[tri[2]] - x[tri[0]]).normalized();
    for (int e = 0; e < 3; ++e) {
      const int a = tri[e], b = tri[(e + 1) % 3];
      const auto key = std::make_pair(std::min(a, b), std::max(a, b));
      const auto it = first_of_edge.find(key);
      if (it == first_of_edge.end()) {
        first_of_edge.emplace(key, t);
      } else {
        const double c = std::clamp(normal[t].dot(normal[it->second]), -1.0, 1.0);
        sum += std::acos(c) * 180.0 / M_PI;
        ++pairs;
      }
    }
  }
  return pairs ? sum / pairs : 0.0;
}

// The footprint's raster cell, m: 2 mm, fine against the 1 cm and more by which drapes
// differ, coarse enough for a million-cell grid on a metre of cloth.
constexpr double kFootprintCell = 2e-3;

double footprint(const Model& m, const Vec3List& x) {
  return testing::projected_area(x, m.triangles, kFootprintCell);
}

std::pair<std::string, double> integrator_and_dt(const std::string& text,
                                                 std::vector<std::string>* extra) {
  std::vector<std::string> parts;
  std::stringstream in(text);
  std::string part;
  while (std::getline(in, part, ':')) parts.push_back(part);
  if (parts.size() < 2) {
    std::fprintf(stderr, "tissu_drape_bench: %s: expected INTEGRATOR:DT[:KEY=VALUE,...]\n",
                 text.c_str());
    std::exit(2);
  }
  if (parts.size() > 2 && extra) {
    std::stringstream keys(parts[2]);
    while (std::getline(keys, part, ',')) extra->push_back(part);
  }
  return {parts[0], std::atof(parts[1].c_str())};
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: tissu_drape_bench SCENE [--set K=V]... [--reference I:DT] "
                         "[--cache FILE] [--fps F] VARIANT...\n");
    return 2;
  }
  const std::string scene_file = argv[1];
  std::vector<std::string> overrides, variants;
  std::string reference_spec, cache;
  double fps = 30.0;
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--set" && i + 1 < argc) {
      overrides.push_back(argv[++i]);
    } else if (a == "--reference" && i + 1 < argc) {
      reference_spec = argv[++i];
    } else if (a == "--cache" && i + 1 < argc) {
      cache = argv[++i];
    } else if (a == "--fps" && i + 1 < argc) {
      fps = std::atof(argv[++i]);
    } else {
      variants.push_back(a);
    }
  }
  const Scene base = load_scene(scene_file, overrides);
  const Simulation sim = build_simulation(base);
  if (reference_spec.empty()) {
    if (!is_explicit(base.integrator)) {
      std::fprintf(stderr, "tissu_drape_bench: %s: the scene's integrator is %s; give "
                           "--reference INTEGRATOR:DT, an explicit one at a stable step\n",
                   scene_file.c_str(), integrator_name(base.integrator));
      return 2;
    }
    reference_spec = "symplectic_euler:" + std::to_string(base.dt);
  }

  Run reference;
  if (cache.empty() || !load(reference.frames, cache)) {
    const auto [integrator, dt] = integrator_and_dt(reference_spec, nullptr);
    reference = simulate(scene_file, overrides, integrator, dt, fps);
    std::printf("reference %s: %s, %.4f ms/step\n", reference_spec.c_str(),
                reference.status.c_str(), reference.ms_per_step);
    if (!cache.empty()) save(reference.frames, cache);
  }
  const Vec3List& ref_last = reference.frames.x.back();
  std::printf("reference at the last frame: compressed %.2f %%, normal angle %.2f deg, "
              "footprint %.4f m^2\n",
              compressed_share(sim.model, ref_last), mean_normal_angle(sim.model, ref_last),
              footprint(sim.model, ref_last));
  std::printf("%-46s %-10s %9s %7s %11s %11s %10s %9s %12s\n", "variant", "status", "ms/step",
              "steps", "centroid cm", "compressed%", "angle deg", "gain J", "footprint m2");
  for (const std::string& v : variants) {
    std::vector<std::string> extra = overrides;
    const auto [integrator, dt] = integrator_and_dt(v, &extra);
    const Run run = simulate(scene_file, extra, integrator, dt, fps);
    const size_t frames = std::min(run.frames.x.size(), reference.frames.x.size());
    double sum = 0.0;
    for (size_t k = 0; k < frames; ++k) {
      const double gap = centroid_z(run.frames.x[k]) - centroid_z(reference.frames.x[k]);
      sum += gap * gap;
    }
    const Vec3List& last = run.frames.x.back();
    std::printf("%-46s %-10s %9.3f %7lld %11.3f %11.2f %10.2f %9.3g %12.4f\n", v.c_str(),
                run.status.substr(0, 10).c_str(), run.ms_per_step, run.steps,
                100.0 * std::sqrt(sum / std::max<size_t>(1, frames)),
                compressed_share(sim.model, last), mean_normal_angle(sim.model, last),
                run.max_energy_gain, footprint(sim.model, last));
    if (run.status != "ok") std::printf("  %s\n", run.status.c_str());
    std::fflush(stdout);
  }
  return 0;
}
