// Speed of `tissu render` per stage: simulate, draw, read back and encode, in ms per video
// frame (wall and CPU time), and the frames produced per second end to end.
//
//   tissu_render_bench [SCENE.json] [--frames N] [--msaa 4,1,fxaa] [--set KEY=VALUE]... [--threads N]
//                      [--replay] [--passes] [--out DIR] [--png DIR]
//
// Default: the demo scene (scenes/demo.json), all its frames, MSAA 4 then 1 ("fxaa": one
// sample and FXAA, render/image/fxaa.h). For each setting
// the scene is simulated and rendered to an MP4 in DIR (default: a temporary directory)
// exactly as `tissu render` does it (RenderSink: drawing and encoding overlap the
// simulation), and the times are printed. --png DIR also writes every frame as a PNG.
//   --replay  simulate the frames once first, then time rendering and encoding alone
//             (feeding the stored states as fast as the renderer takes them).
//   --passes  like --replay without video, timing each renderer pass (glFinish after
//             every pass, so the sum is a little above the normal frame time).
// CPU times: the simulation thread (thread CPU clock), the render thread, llvmpipe's
// rasterizer threads (/proc/self/task/*/schedstat), and the encoder as the rest of the
// process's CPU time. On a loaded machine the CPU times are the better guide; the load
// average is printed before and after.
#include <sys/utsname.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "app/render_sink.h"
#include "app/run_loop.h"
#include "physics/diagnostics.h"
#include "physics/parallel.h"
#include "render/cpu_clock.h"
#include "scene/scene.h"

using namespace tissu;

namespace {

namespace fs = std::filesystem;

std::string load_average() {
  std::ifstream in("/proc/loadavg");
  std::string a, b, c;
  in >> a >> b >> c;
  return a + " " + b + " " + c;
}

// CPU time of the simulation's helper threads, and with the calling thread's.
double helpers_cpu_seconds() { return named_threads_cpu_seconds(kSimulationHelperThreadName); }
double sim_cpu_seconds() { return thread_cpu_seconds() + helpers_cpu_seconds(); }

struct Options {
  std::string scene = std::string(TISSU_SOURCE_DIR) + "/scenes/demo.json";
  long long frames = -1;  // all
  std::vector<int> msaa = {4, 1};
  std::vector<std::string> overrides;
  bool replay = false;
  bool passes = false;
  bool serial = false;  // draw on the simulation thread (no render thread)
  int threads = available_processors();  // simulation threads, as tissu render
  std::string out_dir;
  std::string states_file;  // --replay: load the states from here, or save them here
  std::string png_dir;      // also write every frame as a PNG here
};

constexpr int kFxaa = -1;  // in the --msaa list: one sample, then FXAA

std::string aa_name(int msaa) { return msaa == kFxaa ? "FXAA" : "MSAA " + std::to_string(msaa); }

std::vector<int> parse_list(const std::string& text) {
  std::vector<int> values;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) values.push_back(item == "fxaa" ? kFxaa : std::atoi(item.c_str()));
  return values;
}

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "render_bench: %s needs a value\n", a.c_str());
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "--frames") o.frames = std::atoll(value().c_str());
    else if (a == "--msaa") o.msaa = parse_list(value());
    else if (a == "--set") o.overrides.push_back(value());
    else if (a == "--replay") o.replay = true;
    else if (a == "--serial") o.serial = true;
    else if (a == "--threads") o.threads = std::max(1, std::atoi(value().c_str()));
    else if (a == "--passes") o.passes = o.replay = true;
    else if (a == "--out") o.out_dir = value();
    else if (a == "--states") o.states_file = value();
    else if (a == "--png") o.png_dir = value();
    else if (a.rfind("--", 0) == 0 || a == "-h") {
      std::fprintf(stderr,
                   "usage: tissu_render_bench [SCENE.json] [--frames N] [--msaa 4,1,fxaa] "
                   "[--set KEY=VALUE]... [--replay] [--passes] [--serial] [--threads N] [--states FILE] "
                   "[--png DIR] "
                   "[--out DIR]\n");
      std::exit(a == "-h" || a == "--help" ? 0 : 2);
    } else {
      o.scene = a;
    }
  }
  return o;
}

// One frame of a run, kept for replaying.
struct StoredFrame {
  State state;
  FrameStats stats;
};

// The replayed states in a file (positions and times only: what rendering needs), so that
// repeated measurements need not simulate again. Same scene, same frame count, same machine.
void save_states(const std::string& path, const std::vector<StoredFrame>& frames) {
  std::ofstream out(path, std::ios::binary);
  const long long n = static_cast<long long>(frames.size());
  out.write(reinterpret_cast<const char*>(&n), sizeof n);
  for (const StoredFrame& f : frames) {
    const long long v = static_cast<long long>(f.state.x.size());
    out.write(reinterpret_cast<const char*>(&v), sizeof v);
    out.write(reinterpret_cast<const char*>(&f.state.t), sizeof f.state.t);
    out.write(reinterpret_cast<const char*>(f.state.x.data()),
              static_cast<std::streamsize>(v * sizeof(Vec3)));
  }
  if (!out) throw std::runtime_error("cannot write " + path);
}

bool load_states(const std::string& path, const Simulation& sim, long long frames,
                 std::vector<StoredFrame>& out) {
  std::ifstream in(path, std::ios::binary);
  long long n = 0;
  if (!in.read(reinterpret_cast<char*>(&n), sizeof n) || n != frames) return false;
  for (long long i = 0; i < n; ++i) {
    long long v = 0;
    StoredFrame f;
    in.read(reinterpret_cast<char*>(&v), sizeof v);
    in.read(reinterpret_cast<char*>(&f.state.t), sizeof f.state.t);
    if (!in || v != static_cast<long long>(sim.state.x.size())) return false;
    f.state.x.resize(static_cast<size_t>(v));
    in.read(reinterpret_cast<char*>(f.state.x.data()), static_cast<std::streamsize>(v * sizeof(Vec3)));
    f.state.v = sim.state.v;
    f.stats.time = f.state.t;
    out.push_back(std::move(f));
  }
  return static_cast<bool>(in);
}

struct Totals {
  long long frames = 0;
  long long steps = 0;
  double sim_wall = 0, sim_cpu = 0;    // simulation thread and its helper threads
  double main_cpu = 0;                 // whole main thread over the loop and finish()
  double helpers_cpu = 0;              // the simulation's helper threads
  double frame_call_wall = 0;          // RenderSink::frame() as seen by the simulation thread
  double finish_wall = 0;              // RenderSink::finish()
  double wall = 0, process_cpu = 0;    // loop + finish
};

void print_results(const char* what, int msaa, const RenderSettings& settings, const Totals& t,
                   const RenderSink& sink) {
  StageTimes st;
  sink.add_times(st);
  const RenderCpuTimes c = sink.cpu_times();
  const double n = static_cast<double>(t.frames);
  const double encoder_cpu = std::max(
      0.0, t.process_cpu - t.main_cpu - t.helpers_cpu - c.thread_total - c.rasterizer);
  auto ms = [&](double s) { return 1e3 * s / n; };
  std::printf("\n== %s, %s, %dx%d, %lld frames (%.0f simulation steps per frame)\n", what,
              aa_name(msaa).c_str(), settings.width, settings.height, t.frames,
              t.frames > 1 ? static_cast<double>(t.steps) / (n - 1) : 0.0);
  std::printf("  %-44s %12s %12s\n", "stage, per frame", "wall ms", "CPU ms");
  if (t.steps > 0) {
    std::printf("  %-44s %12.1f %12.1f\n", "simulate (simulation threads)", ms(t.sim_wall),
                ms(t.sim_cpu));
  }
  const char* drawer = c.thread_total > 0 ? "render thread" : "simulation thread";
  std::printf("  %-44s %12.1f %12.1f\n", (std::string("draw (") + drawer + ")").c_str(),
              ms(st.render), ms(c.draw));
  std::printf("  %-44s %12.1f %12.1f\n", (std::string("read back (") + drawer + ")").c_str(),
              ms(st.readback), ms(c.readback));
  if (c.thread_total > 0) {
    std::printf("  %-44s %12s %12.1f\n", "render thread, all", "", ms(c.thread_total));
  }
  std::printf("  %-44s %12s %12.1f\n", "llvmpipe rasterizer threads", "", ms(c.rasterizer));
  std::printf("  %-44s %12.1f %12.1f\n", "encode (worker: busy wall; CPU = rest)", ms(st.encode),
              ms(encoder_cpu));
  std::printf("  %-44s %12.1f\n", (std::string("waiting for the encoder queue (") + drawer + ")").c_str(),
              ms(sink.encoder_queue_wait_seconds()));
  if (c.thread_total > 0) {
    std::printf("  %-44s %12.1f\n", "waiting for the render queue (simulation)",
                ms(st.encode_wait));
  }
  std::printf("  %-44s %12.1f\n", "RenderSink::frame() on the simulation thread",
              ms(t.frame_call_wall));
  std::printf("  %-44s %12.1f\n", "RenderSink::finish() (drains the queues)",
              ms(t.finish_wall));
  std::printf("  %-44s %12.1f %12.1f\n", "all, end to end (CPU: whole process)", ms(t.wall),
              ms(t.process_cpu));
  std::printf("  end to end: %.2f frames/s (wall); CPU %.1f ms per frame = %.1f frames/s if "
              "the %ld cores were all ours\n",
              n / t.wall, ms(t.process_cpu), n / t.process_cpu * sysconf(_SC_NPROCESSORS_ONLN),
              sysconf(_SC_NPROCESSORS_ONLN));
  const std::vector<RenderPassTime> passes = sink.pass_times();
  if (!passes.empty()) {
    double cpu = 0, wall = 0;
    std::printf("  %-44s %12s %12s\n", "renderer pass (glFinish after each)", "wall ms",
                "CPU ms");
    for (const RenderPassTime& p : passes) {
      const double k = static_cast<double>(std::max<long long>(1, p.count));
      std::printf("    %-42s %12.2f %12.2f\n", p.pass.c_str(), 1e3 * p.wall_s / k,
                  1e3 * p.cpu_s / k);
      cpu += p.cpu_s / k;
      wall += p.wall_s / k;
    }
    std::printf("    %-42s %12.2f %12.2f\n", "sum", 1e3 * wall, 1e3 * cpu);
  }
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  const Options options = parse(argc, argv);
  try {
    const Scene scene = load_scene(options.scene, options.overrides);
    RenderSettings settings = render_settings_of(scene);
    const long long every = steps_per_frame(scene.dt, frames_per_simulated_second(settings));
    const long long scene_frames = scene.steps / every + 1;
    const long long frames =
        options.frames > 0 ? std::min(options.frames, scene_frames) : scene_frames;
    const fs::path out = options.out_dir.empty()
                             ? fs::temp_directory_path() / ("tissu_render_bench_" +
                                                            std::to_string(getpid()))
                             : fs::path(options.out_dir);
    fs::create_directories(out);
    const char* lp_threads = std::getenv("LP_NUM_THREADS");
    std::printf("scene %s: %s, dt %g s, %lld steps per frame, %lld frames, %d simulation threads\n",
                options.scene.c_str(), integrator_name(scene.integrator), scene.dt, every,
                frames, options.threads);
    std::printf("%ld cores online, LP_NUM_THREADS=%s, load average before: %s\n",
                sysconf(_SC_NPROCESSORS_ONLN), lp_threads ? lp_threads : "(unset)",
                load_average().c_str());

    // --replay: the states of every frame, simulated once.
    std::vector<StoredFrame> stored;
    Totals replay_sim;
    if (options.replay && !options.states_file.empty() &&
        load_states(options.states_file, build_simulation(scene), frames, stored)) {
      std::printf("states of %lld frames read from %s\n", frames, options.states_file.c_str());
    } else if (options.replay) {
      stored.clear();
      Simulation sim = build_simulation(scene);
      Workspace ws;
      ws.threads = options.threads;
      const double w0 = wall_seconds(), c0 = sim_cpu_seconds();
      for (long long f = 0; f < frames; ++f) {
        for (long long s = 0; f > 0 && s < every; ++s) {
          if (step(sim.model, sim.state, ws)) {
            std::fprintf(stderr, "render_bench: the simulation diverged\n");
            return 3;
          }
          ++replay_sim.steps;
        }
        stored.push_back({sim.state, measure_frame(sim.model, sim.state)});
      }
      replay_sim.sim_wall = wall_seconds() - w0;
      replay_sim.sim_cpu = sim_cpu_seconds() - c0;
      std::printf("simulated %lld frames first: %.1f ms wall, %.1f ms CPU per frame\n", frames,
                  1e3 * replay_sim.sim_wall / frames, 1e3 * replay_sim.sim_cpu / frames);
      if (!options.states_file.empty()) save_states(options.states_file, stored);
    }

    for (int msaa : options.msaa) {
      settings.fxaa = msaa == kFxaa;
      settings.msaa = settings.fxaa ? 1 : msaa;
      Simulation sim = build_simulation(scene);
      RenderOutputs outputs;
      if (!options.passes) outputs.mp4_path = (out / (scene.name + ".mp4")).string();
      outputs.max_frames = frames;
      if (!options.png_dir.empty()) {
        outputs.png_dir = (fs::path(options.png_dir) / (settings.fxaa ? std::string("fxaa") : "msaa" + std::to_string(msaa))).string();
        fs::create_directories(outputs.png_dir);
      }
      outputs.pass_timing = options.passes;
      outputs.render_thread = !options.serial;
      RenderSink sink(settings, outputs);

      Totals t;
      Workspace ws;
      ws.threads = options.threads;
      const double wall0 = wall_seconds(), process0 = process_cpu_seconds();
      const double main0 = thread_cpu_seconds(), helpers0 = helpers_cpu_seconds();
      for (long long f = 0; f < frames; ++f) {
        const Model& model = sim.model;
        FrameStats stats;
        const State* state = &sim.state;
        if (options.replay) {
          state = &stored[static_cast<size_t>(f)].state;
          stats = stored[static_cast<size_t>(f)].stats;
        } else {
          const double w = wall_seconds(), c = sim_cpu_seconds();
          for (long long s = 0; f > 0 && s < every; ++s) {
            if (step(model, sim.state, ws)) {
              std::fprintf(stderr, "render_bench: the simulation diverged\n");
              sink.abort();
              return 3;
            }
            ++t.steps;
          }
          t.sim_wall += wall_seconds() - w;
          t.sim_cpu += sim_cpu_seconds() - c;
          stats = measure_frame(model, sim.state);
        }
        const double w = wall_seconds();
        sink.frame(model, *state, stats);
        t.frame_call_wall += wall_seconds() - w;
        ++t.frames;
      }
      const double w = wall_seconds();
      sink.finish();
      t.finish_wall = wall_seconds() - w;
      t.wall = wall_seconds() - wall0;
      t.process_cpu = process_cpu_seconds() - process0;
      t.main_cpu = thread_cpu_seconds() - main0;
      t.helpers_cpu = helpers_cpu_seconds() - helpers0;
      print_results(options.passes ? "renderer passes (replayed states, no video)"
                    : options.replay ? "render and encode (replayed states)"
                                     : "simulate, render and encode",
                    msaa, settings, t, sink);
    }
    std::printf("\nload average after: %s\n", load_average().c_str());
    if (options.out_dir.empty()) fs::remove_all(out);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "render_bench: %s\n", e.what());
    return 1;
  }
  return 0;
}
