// The tissu program end to end: exit codes, reports, OBJ output, nothing written on bad
// input, interrupt handling.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

#include "common/tissu_shell.h"

namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

using Result = tissu::test::ShellResult;
using tissu::test::read_text;

class Cli : public tissu::test::TempDirTest {
 protected:
  Cli() : TempDirTest("tissu_cli") {}

  std::string write_scene(const std::string& name, const Json& scene) {
    const std::string path = (dir_ / name).string();
    std::ofstream(path) << scene.dump(2);
    return path;
  }

  // Runs tissu with `args`; stderr captured.
  Result run(const std::string& args) {
    return tissu::test::run_tissu_shell(args, dir_ / "stderr.txt");
  }

  static Json small_scene() {
    return Json::parse(R"({
      "name": "small", "dt": 1e-4, "steps": 300, "integrator": "symplectic_euler",
      "cloth": {"mesh": {"generate": "rectangle", "size": [0.4, 0.3], "triangles": 150,
                         "irregular": true, "seed": 2},
                "material": "silk",
                "transform": {"rotate": {"axis": [1, 0, 0], "degrees": 90}},
                "pins": [{"box": {"min": [-1, -1, 0.149], "max": [1, 1, 1]}}]},
      "gravity": [0, 0, -9.81], "air_damping": 0.2
    })");
  }

  Json read_json(const fs::path& p) {
    std::ifstream in(p);
    return Json::parse(in);
  }
};

TEST_F(Cli, HelpListsEveryOption) {
  const std::string out = (dir_ / "help.txt").string();
  ASSERT_EQ(std::system((std::string(TISSU_BINARY) + " run --help > " + out).c_str()), 0);
  std::ifstream in(out);
  std::stringstream ss;
  ss << in.rdbuf();
  for (const char* option : {"--out", "--set", "--obj-every", "--threads", "--report"}) {
    EXPECT_NE(ss.str().find(option), std::string::npos) << option;
  }
}

TEST_F(Cli, RunWritesReportAndObjFiles) {
  const std::string scene = write_scene("s.json", small_scene());
  const fs::path out = dir_ / "out";
  const Result r = run("run " + scene + " --out " + out.string() + " --obj-every 100 --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Json report = read_json(out / "report.json");
  EXPECT_EQ(report["scene"], "small");
  EXPECT_EQ(report["status"], "ok");
  EXPECT_EQ(report["steps_requested"], 300);
  EXPECT_EQ(report["steps_done"], 300);
  EXPECT_EQ(report["integrator"], "symplectic_euler");
  EXPECT_TRUE(report["divergence"].is_null());
  EXPECT_GT(report["triangles"].get<int>(), 100);
  EXPECT_GT(report["ms_per_step"].get<double>(), 0.0);
  // 300 steps of 1e-4 s end between the frames at 0 and 1/30 s: the end is its own row.
  ASSERT_EQ(report["frames"].size(), 1u);
  ASSERT_TRUE(report.contains("end"));
  const Json& last = report["end"];
  EXPECT_EQ(last["step"], 300);
  EXPECT_GT(last["kinetic_energy"].get<double>(), 0.0);
  EXPECT_GT(last["elastic_energy"].get<double>(), 0.0);
  EXPECT_TRUE(last["min_clearance"].is_null()) << "no obstacles, no clearance";
  for (const char* f : {"frame_000000.obj", "frame_000100.obj", "frame_000200.obj",
                        "frame_000300.obj", "final.obj"}) {
    EXPECT_TRUE(fs::exists(out / "obj" / f)) << f;
  }
  // The OBJ keeps the vertex count and writes rest (u, v) as texture coordinates.
  std::ifstream obj(out / "obj" / "final.obj");
  int v = 0, vt = 0, f = 0;
  for (std::string line; std::getline(obj, line);) {
    if (line.rfind("v ", 0) == 0) ++v;
    if (line.rfind("vt ", 0) == 0) ++vt;
    if (line.rfind("f ", 0) == 0) ++f;
  }
  EXPECT_EQ(v, report["vertices"].get<int>());
  EXPECT_EQ(vt, v);
  EXPECT_EQ(f, report["triangles"].get<int>());
}

TEST_F(Cli, BadInputExitsTwoAndWritesNothing) {
  Json scene = small_scene();
  scene["cloth"]["material"] = Json::parse(
      R"({"density": -1, "stiffness": {"weft": 100, "warp": 100, "shear": 10}})");
  const std::string path = write_scene("bad.json", scene);
  const fs::path out = dir_ / "out";
  const Result r = run("run " + path + " --out " + out.string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err, "tissu: " + path + ": cloth.material.density: must be > 0, got -1\n");
  EXPECT_FALSE(fs::exists(out));
}

TEST_F(Cli, BadOverrideAndUsageExitTwo) {
  const std::string path = write_scene("s.json", small_scene());
  const fs::path out = dir_ / "out";
  Result r = run("run " + path + " --out " + out.string() + " --set cloth.materiall=silk");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--set cloth.materiall=silk: cloth.materiall: unknown key"),
            std::string::npos)
      << r.err;
  r = run("run " + path + " --frobnicate");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err, "tissu run: unknown option --frobnicate (see tissu run --help)\n");
  r = run("run " + path + " --threads 0");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err, "tissu: --threads: expected an integer >= 1, got \"0\"\n");
  r = run("run " + path + " --threads 100000");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err, "tissu: --threads: expected at most 256, got 100000\n");
  r = run("run");
  EXPECT_EQ(r.exit_code, 2);
  r = run("fly " + path);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_FALSE(fs::exists(out));
}

TEST_F(Cli, OverridesOfAPresetFieldAndOfStepsOnTheDemo) {
  // demo.json names its material by preset and gives a duration: a field of the preset
  // and the step count are overridden all the same.
  const std::string demo = (fs::path(TISSU_SOURCE_DIR) / "scenes" / "demo.json").string();
  const fs::path out = dir_ / "out";
  Result r = run("run " + demo + " --out " + out.string() +
                 " --quiet --set steps=2 --set cloth.material.density=0.2");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(read_json(out / "report.json")["steps_done"], 2);
  // A field the material has not is still one line naming the override and the place.
  r = run("run " + demo + " --out " + (dir_ / "out2").string() +
          " --quiet --set steps=2 --set cloth.material.densty=0.2");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err, "tissu: --set cloth.material.densty=0.2: cloth.material.densty: unknown key "
                   "(did you mean \"cloth.material.density\"?)\n");
  EXPECT_FALSE(fs::exists(dir_ / "out2"));
}

TEST_F(Cli, OutputDirectoryThatCannotBeCreated) {
  const std::string path = write_scene("s.json", small_scene());
  std::ofstream(dir_ / "file") << "x";
  const Result r = run("run " + path + " --out " + (dir_ / "file" / "sub").string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("cannot create output directory"), std::string::npos) << r.err;
}

TEST_F(Cli, DivergenceExitsThreeWithStepAndVertex) {
  Json scene = small_scene();
  scene["integrator"] = "explicit_euler";
  scene["dt"] = 2e-3;  // far beyond the explicit stability limit
  scene["cloth"]["transform"]["scale"] = 1.05;
  const std::string path = write_scene("d.json", scene);
  const fs::path out = dir_ / "out";
  const Result r = run("run " + path + " --out " + out.string() + " --obj-every 1000 --quiet");
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_NE(r.err.find("diverged at step"), std::string::npos) << r.err;
  const Json report = read_json(out / "report.json");
  EXPECT_EQ(report["status"], "diverged");
  EXPECT_GE(report["divergence"]["step"].get<int>(), 1);
  EXPECT_GE(report["divergence"]["vertex"].get<int>(), 0);
  EXPECT_LT(report["steps_done"].get<int>(), 300);
  EXPECT_TRUE(fs::exists(out / "obj" / "final.obj"));
}

// The paper's position correction with an implicit integrator is warned about in one line
// (it tears a sheet dropped on a sphere at 1/30 s, docs/paper.md); with the explicit
// integrators it is made for, nothing is said.
TEST_F(Cli, PositionCorrectionWithAnImplicitIntegratorIsWarnedAbout) {
  Json scene = small_scene();
  scene["steps"] = 2;
  scene["position_correction"] = {{"threshold", 0.01}};
  const std::string quiet = write_scene("explicit.json", scene);
  Result r = run("run " + quiet + " --out " + (dir_ / "a").string() + " --quiet");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err.find("warning"), std::string::npos) << r.err;
  scene["integrator"] = "backward_euler";
  scene["dt"] = 1.0 / 30.0;
  const std::string path = write_scene("implicit.json", scene);
  r = run("run " + path + " --out " + (dir_ / "b").string() + " --quiet");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("warning: " + path + ": position_correction with backward_euler"),
            std::string::npos)
      << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
}

// The divergence message points at a step that works, and that step does work: the same
// scene run with it gets past the time the hint checked.
TEST_F(Cli, DivergenceHintGivesAStepThatRuns) {
  Json scene = small_scene();
  scene["dt"] = 2e-3;  // far beyond symplectic Euler's limit on silk
  scene["steps"] = 100;
  const std::string path = write_scene("d.json", scene);
  Result r = run("run " + path + " --out " + (dir_ / "a").string() + " --quiet");
  ASSERT_EQ(r.exit_code, 3) << r.err;
  EXPECT_NE(r.err.find("without diverging"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("tissu stability " + path + " --integrators symplectic_euler"),
            std::string::npos) << r.err;
  const Json hint = read_json(dir_ / "a" / "report.json")["divergence"]["hint"];
  ASSERT_TRUE(hint["working_dt"].is_number()) << hint.dump();
  const double dt = hint["working_dt"].get<double>();
  const double until = hint["checked_until"].get<double>();
  EXPECT_LT(dt, 2e-3);
  EXPECT_GE(hint["smallest_failed_dt"].get<double>(), 2 * dt * 0.999);
  const long long steps = static_cast<long long>(std::ceil(until / dt - 1e-9));
  r = run("run " + path + " --out " + (dir_ / "b").string() + " --quiet --set dt=" +
          std::to_string(dt) + " --set steps=" + std::to_string(steps));
  EXPECT_EQ(r.exit_code, 0) << r.err;
}

TEST_F(Cli, SigintStopsTheRunAndReportsInterrupted) {
  Json scene = small_scene();
  scene["steps"] = 100000000;
  const std::string path = write_scene("long.json", scene);
  const fs::path out = dir_ / "out";
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    const std::string out_arg = out.string();
    execl(TISSU_BINARY, TISSU_BINARY, "run", path.c_str(), "--out", out_arg.c_str(), "--quiet",
          static_cast<char*>(nullptr));
    _exit(127);
  }
  // Wait until the run has started (its output directory exists), then interrupt it.
  for (int i = 0; i < 600 && !fs::exists(out); ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  kill(pid, SIGINT);
  int status = 0;
  waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 130);
  const Json report = read_json(out / "report.json");
  EXPECT_EQ(report["status"], "interrupted");
  EXPECT_GT(report["steps_done"].get<long long>(), 0);
  EXPECT_LT(report["steps_done"].get<long long>(), 100000000);
}

}  // namespace

namespace {

// A free sheet falling under gravity with backward Euler at dt = 0.004 s, recorded at 30
// frames per second: 0.004 does not divide 1/30, so most frame times fall between steps.
Json falling_scene(double duration) {
  Json scene = Json::parse(R"({
    "name": "fall", "dt": 0.004, "integrator": "backward_euler",
    "cloth": {"mesh": {"generate": "rectangle", "size": [0.2, 0.2], "triangles": 50,
                       "irregular": true, "seed": 3},
              "material": "silk"},
    "gravity": [0, 0, -9.81],
    "render": {"width": 64, "height": 48, "msaa": 1, "fps": 30}
  })");
  scene["duration"] = duration;
  return scene;
}

// Backward Euler free fall from rest: z_n = -g h^2 n (n + 1) / 2 exactly.
double fall_height(double t, double h) {
  const double steps = t / h;
  const long long n = static_cast<long long>(std::floor(steps + 1e-9));
  const double w = steps - static_cast<double>(n);
  auto z = [h](double k) { return -9.81 * h * h * k * (k + 1.0) / 2.0; };
  return std::fabs(w) < 1e-9 ? z(n) : (1.0 - w) * z(n) + w * z(n + 1);
}

}  // namespace

// Frames are at exactly k / fps, whatever the step: frame k of a 2 s run at 30 fps is at
// k / 30 s, and shows the state there (positions interpolated between the two steps around
// it, which for a falling sheet puts its gravity potential on the line between theirs).
TEST_F(Cli, FramesAreAtExactFrameTimesWhateverTheStep) {
  const std::string scene = write_scene("fall.json", falling_scene(2.0));
  const fs::path out = dir_ / "out";
  const Result r = run("run " + scene + " --out " + out.string() + " --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Json report = read_json(out / "report.json");
  const Json& frames = report["frames"];
  ASSERT_EQ(frames.size(), 61u);
  const double end_height = fall_height(2.0, 0.004);
  const double end_potential = frames.back()["potential_energy"].get<double>();
  for (size_t k = 0; k < frames.size(); ++k) {
    const double t = static_cast<double>(k) / 30.0;
    EXPECT_NEAR(frames[k]["time"].get<double>(), t, 1e-12) << k;
    if (k == 0) continue;
    // The potential (relative to the start) is M g z: its ratio to the end's is z's.
    const double start = frames[0]["potential_energy"].get<double>();
    const double ratio = (frames[k]["potential_energy"].get<double>() - start) / (end_potential - start);
    EXPECT_NEAR(ratio, fall_height(t, 0.004) / end_height, 1e-9) << "frame " << k;
  }
}

// A video is as long as the scene: 0.5 s at 30 fps are frames 0 to 15, written as 16 PNGs
// (a frame every 8 steps of 0.004 s would make them 0.032 s apart and the clip 4% slow).
TEST_F(Cli, RenderWritesOneFramePerFrameTime) {
  const std::string scene = write_scene("fall.json", falling_scene(0.5));
  const fs::path out = dir_ / "out";
  const Result r = run("render " + scene + " --out " + out.string() + " --png --no-mp4 --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  int pngs = 0;
  for (const auto& entry : fs::directory_iterator(out / "png")) pngs += entry.path().extension() == ".png";
  EXPECT_EQ(pngs, 16);
  const Json report = read_json(out / "report.json");
  ASSERT_EQ(report["frames"].size(), 16u);
  EXPECT_NEAR(report["frames"].back()["time"].get<double>(), 0.5, 1e-12);
}

namespace {

// The files directly in `dir` (names, sorted); none when it does not exist.
std::vector<std::string> names_in(const fs::path& dir) {
  std::vector<std::string> out;
  if (!fs::exists(dir)) return out;
  for (const auto& entry : fs::directory_iterator(dir)) out.push_back(entry.path().filename().string());
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<std::string> numbered_pngs(std::initializer_list<int> frames) {
  std::vector<std::string> out;
  for (int k : frames) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%06d.png", k);
    out.push_back(name);
  }
  return out;
}

}  // namespace

// --png and --stills together write both: every frame to png/, and the stills to stills/.
TEST_F(Cli, PngSequenceAndStillsAreBothWritten) {
  const std::string scene = write_scene("fall.json", falling_scene(0.5));
  const fs::path out = dir_ / "out";
  const Result r =
      run("render " + scene + " --out " + out.string() + " --png --stills 2 --no-mp4 --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(names_in(out / "png").size(), 16u);
  EXPECT_EQ(names_in(out / "stills"), numbered_pngs({7, 15}));
}

// Usage errors name the command once: "tissu render: ...", not "tissu: tissu render: ...".
TEST_F(Cli, UsageErrorsNameTheCommandOnce) {
  const std::string path = write_scene("s.json", small_scene());
  Result r = run("render " + path + " --frobnicate");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err, "tissu render: unknown option --frobnicate (see tissu render --help)\n");
  r = run("render");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err, "tissu render: missing SCENE.json (see --help)\n");
  r = run("render " + path + " --out");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err, "tissu render: --out needs a value\n");
}

// A bad value in the scene's render block names the scene file, as every scene error does.
TEST_F(Cli, RenderBlockErrorsNameTheSceneFile) {
  Json scene = falling_scene(0.5);
  scene["render"]["fps"] = -1;
  const std::string path = write_scene("bad.json", scene);
  const fs::path out = dir_ / "out";
  for (const char* command : {"render", "run"}) {
    const Result r = run(std::string(command) + " " + path + " --out " + out.string());
    EXPECT_EQ(r.exit_code, 2) << command;
    EXPECT_EQ(r.err.rfind("tissu: " + path + ": render.fps: ", 0), 0u) << r.err;
    EXPECT_FALSE(fs::exists(out));
  }
  // A value set with --set is named by the override, as for the rest of the scene.
  const Result r = run("render " + write_scene("s.json", falling_scene(0.5)) + " --out " +
                       out.string() + " --set render.fps=0");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err.rfind("tissu: --set render.fps=0: render.fps: ", 0), 0u) << r.err;
}

// --frames N stops the run before the scene's steps are all done: the report says so.
TEST_F(Cli, FramesLimitReportsStopped) {
  const std::string scene = write_scene("fall.json", falling_scene(0.5));
  const fs::path out = dir_ / "out";
  const Result r =
      run("render " + scene + " --out " + out.string() + " --frames 5 --png --no-mp4 --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(names_in(out / "png"), numbered_pngs({0, 1, 2, 3, 4}));
  const Json report = read_json(out / "report.json");
  EXPECT_EQ(report["status"], "stopped");
  EXPECT_EQ(report["message"], "stopped at --frames");
  EXPECT_LT(report["steps_done"].get<long long>(), report["steps_requested"].get<long long>());
  EXPECT_NE(r.err.find("tissu: fall: stopped at --frames 5"), std::string::npos) << r.err;

  // As many frames as the scene has, or more: every step is done, status ok.
  const Result all = run("render " + scene + " --out " + (dir_ / "all").string() +
                         " --frames 16 --no-mp4 --quiet");
  ASSERT_EQ(all.exit_code, 0) << all.err;
  const Json whole = read_json(dir_ / "all" / "report.json");
  EXPECT_EQ(whole["status"], "ok");
  EXPECT_EQ(whole["message"], "all steps done");
  EXPECT_EQ(whole["steps_done"], whole["steps_requested"]);

  // In slow motion a step holds several frames: the run still stops at frame N - 1.
  Json slow = falling_scene(0.5);
  slow["dt"] = 0.02;
  slow["render"]["slow_motion"] = 10;  // 300 frames per simulated second, 6 per step
  const fs::path slow_out = dir_ / "slow";
  const Result s = run("render " + write_scene("slow.json", slow) + " --out " +
                       slow_out.string() + " --frames 4 --png --no-mp4 --quiet");
  ASSERT_EQ(s.exit_code, 0) << s.err;
  EXPECT_EQ(names_in(slow_out / "png"), numbered_pngs({0, 1, 2, 3}));
  const Json stopped = read_json(slow_out / "report.json");
  EXPECT_EQ(stopped["status"], "stopped");
  ASSERT_EQ(stopped["frames"].size(), 4u) << "a row per frame written";
  EXPECT_NEAR(stopped["frames"][3]["time"].get<double>(), 3.0 / 300.0, 1e-12);
  ASSERT_TRUE(stopped.contains("end")) << "the state the run ends on, between frame times";
  EXPECT_NEAR(stopped["end"]["time"].get<double>(), 0.02, 1e-12);
}

// The progress line counts video frames and simulated time, ffmpeg-like.
TEST_F(Cli, ProgressShowsFramesAndSimulatedTime) {
  const std::string scene = write_scene("fall.json", falling_scene(0.5));
  Result r = run("render " + scene + " --out " + (dir_ / "a").string() + " --no-mp4 --stills 1");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("render: frame=  16/16 time=0.500s (100%), done in "), std::string::npos)
      << r.err;
  r = run("run " + scene + " --out " + (dir_ / "b").string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("simulate: frame=  16/16 time=0.500s (100%), done in "), std::string::npos)
      << r.err;
  r = run("render " + scene + " --out " + (dir_ / "c").string() + " --no-mp4 --stills 1 --frames 5");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // Frame 4 is at 0.133 s, inside the step that ends at 0.136 s, where the run stops.
  EXPECT_NE(r.err.find("render: frame=   5/5 time=0.136s (100%), done in "), std::string::npos)
      << r.err;
}

// A second run into the same outputs is refused (ffmpeg's convention), in one line that
// names the outputs and the option that replaces them; the earlier run's files stay.
TEST_F(Cli, ExistingOutputsAreRefusedWithoutOverwrite) {
  const std::string scene = write_scene("fall.json", falling_scene(0.5));
  const fs::path out = dir_ / "out";
  const std::string render = "render " + scene + " --out " + out.string() + " --quiet";
  ASSERT_EQ(run(render + " --png --no-mp4").exit_code, 0);
  const std::string report = read_text(out / "report.json");

  Result r = run(render + " --png --no-mp4");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_EQ(r.err, "tissu: " + (out / "png").string() +
                       ": holds frames of an earlier run (16 frame_*.png); use -y (--overwrite)"
                       " to replace them\n");
  EXPECT_EQ(names_in(out / "png").size(), 16u);
  EXPECT_EQ(read_text(out / "report.json"), report);

  // The report, and the video, are outputs of their own.
  r = run(render + " --no-mp4");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_EQ(r.err, "tissu: " + (out / "report.json").string() +
                       ": already exists; use -y (--overwrite) to replace it\n");
  r = run("run " + scene + " --out " + out.string() + " --quiet");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  ASSERT_EQ(run(render + " --report " + (dir_ / "r.json").string()).exit_code, 0);
  r = run(render + " --report " + (dir_ / "r2.json").string());
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_EQ(r.err, "tissu: " + (out / "fall.mp4").string() +
                       ": already exists; use -y (--overwrite) to replace it\n");
  EXPECT_FALSE(fs::exists(dir_ / "r2.json"));
}

// With -y (--overwrite) a shorter run replaces the earlier run's frames, stills, video and
// report instead of mixing its frames with theirs; other files are left alone.
TEST_F(Cli, OverwriteRemovesTheEarlierRunsFramesOnly) {
  const fs::path out = dir_ / "out";
  const std::string long_scene = write_scene("fall.json", falling_scene(0.5));
  ASSERT_EQ(run("render " + long_scene + " --out " + out.string() +
                " --png --stills 3 --obj-every 10 --quiet")
                .exit_code,
            0);
  const std::string first_video = read_text(out / "fall.mp4");
  std::ofstream(out / "notes.txt") << "mine";
  std::ofstream(out / "other.mp4") << "mine";
  std::ofstream(out / "png" / "frame_a.png") << "mine";
  std::ofstream(out / "stills" / "cover.png") << "mine";

  const std::string short_scene = write_scene("short.json", falling_scene(0.2));
  for (const char* option : {"-y", "--overwrite"}) {
    const Result r = run("render " + short_scene + " --out " + out.string() +
                         " --png --stills 2 --obj-every 20 --quiet " + option);
    ASSERT_EQ(r.exit_code, 0) << option << ": " << r.err;
    std::vector<std::string> png = numbered_pngs({0, 1, 2, 3, 4, 5, 6});
    png.push_back("frame_a.png");
    EXPECT_EQ(names_in(out / "png"), png) << option;
    std::vector<std::string> stills = numbered_pngs({3, 6});
    stills.insert(stills.begin(), "cover.png");
    EXPECT_EQ(names_in(out / "stills"), stills) << option;
    EXPECT_EQ(names_in(out / "obj"),
              (std::vector<std::string>{"final.obj", "frame_000000.obj", "frame_000020.obj",
                                        "frame_000040.obj"}))
        << option;
    EXPECT_EQ(read_json(out / "report.json")["frames"].size(), 7u) << option;
    EXPECT_EQ(read_text(out / "notes.txt"), "mine");
  }
  // The video of the scene is replaced; any other file is not this run's output.
  EXPECT_NE(read_text(out / "fall.mp4"), first_video);
  EXPECT_GT(read_text(out / "fall.mp4").size(), 0u);
  EXPECT_EQ(read_text(out / "other.mp4"), "mine");
}

// The report says which Tissu ran what: version and commit, the command line, the --set
// overrides, and the scene as run, which alone reproduces the run.
TEST_F(Cli, ReportHoldsWhatReproducesTheRun) {
  const std::string scene = write_scene("s.json", small_scene());
  const fs::path out = dir_ / "out";
  const Result r = run("run " + scene + " --out " + out.string() +
                       " --set steps=1050 --set cloth.material=cotton --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Json report = read_json(out / "report.json");

  EXPECT_EQ(report["tissu"]["version"], TISSU_PROJECT_VERSION);
  const std::string commit = report["tissu"]["git_commit"];
  EXPECT_TRUE(commit == "unknown" || (commit.size() == 40 &&
              commit.find_first_not_of("0123456789abcdef") == std::string::npos))
      << commit;
  EXPECT_TRUE(report["tissu"]["git_modified"].is_boolean());
  EXPECT_EQ(report["command_line"],
            Json({TISSU_BINARY, "run", scene, "--out", out.string(), "--set", "steps=1050",
                  "--set", "cloth.material=cotton", "--quiet"}));
  EXPECT_EQ(report["overrides"], Json({"steps=1050", "cloth.material=cotton"}));

  const Json& resolved = report["resolved_scene"];
  EXPECT_EQ(resolved["steps"], 1050);
  const Json& material = resolved["cloth"]["material"];
  ASSERT_TRUE(material.is_object()) << material;
  EXPECT_GT(material["density"].get<double>(), 0.0);
  EXPECT_GT(material["stiffness"]["weft"].get<double>(), 0.0);

  // A preset with an override also becomes numbers, the override among them.
  const fs::path out3 = dir_ / "out3";
  const Result r3 = run("run " + scene + " --out " + out3.string() +
                        " --set steps=10 --set cloth.material=cotton"
                        " --set cloth.material.bending=2e-5 --quiet");
  ASSERT_EQ(r3.exit_code, 0) << r3.err;
  const Json overridden = read_json(out3 / "report.json")["resolved_scene"]["cloth"]["material"];
  EXPECT_FALSE(overridden.contains("preset")) << overridden;
  EXPECT_EQ(overridden["bending"], 2e-5) << overridden;
  EXPECT_EQ(overridden["density"], material["density"]) << overridden;

  // The resolved scene, alone and elsewhere, runs to the same frames.
  fs::create_directories(dir_ / "elsewhere");
  const std::string again = write_scene("elsewhere/resolved.json", resolved);
  const fs::path out2 = dir_ / "out2";
  const Result r2 = run("run " + again + " --out " + out2.string() + " --quiet");
  ASSERT_EQ(r2.exit_code, 0) << r2.err;
  const Json report2 = read_json(out2 / "report.json");
  EXPECT_EQ(report2["overrides"], Json::array());
  ASSERT_GE(report["frames"].size(), 3u);
  ASSERT_TRUE(report.contains("end") && report2.contains("end"));  // 0.105 s: between frames
  ASSERT_EQ(report2["frames"].size(), report["frames"].size());
  for (const char* energy : {"kinetic_energy", "elastic_energy", "potential_energy"}) {
    for (size_t i = 0; i < report["frames"].size(); ++i) {
      EXPECT_EQ(report2["frames"][i][energy], report["frames"][i][energy]) << energy << " " << i;
    }
    EXPECT_EQ(report2["end"][energy], report["end"][energy]) << energy;
  }
}

// tissu paper writes under out/ by default: the published results in docs/ change only
// when asked (--out docs).
TEST_F(Cli, PaperWritesUnderOutByDefault) {
  const std::string scenes = std::string(TISSU_SOURCE_DIR) + "/scenes/paper";
  const std::string command = "cd " + dir_.string() + " && " + TISSU_BINARY +
                              " paper --quick --quiet --scenes " + scenes + " 2> err.txt";
  ASSERT_EQ(std::system(command.c_str()), 0) << read_text(dir_ / "err.txt");
  EXPECT_TRUE(fs::exists(dir_ / "out" / "paper" / "paper-results.md"));
  EXPECT_TRUE(fs::exists(dir_ / "out" / "paper" / "paper-results.csv"));
  EXPECT_FALSE(fs::exists(dir_ / "docs"));
}
