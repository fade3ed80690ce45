// tissu on hard cases beyond their limit (divergence is reported, exit code 3, never
// silent), and tissu study / tissu stability end to end on a tiny scene.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <sys/wait.h>
#include <unistd.h>

#include "common/tissu_shell.h"

namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

using Result = tissu::test::ShellResult;
using tissu::test::read_text;

// Width and height from a PNG's IHDR chunk (bytes 16-23, big-endian); 0 x 0 if not a PNG.
std::pair<int, int> png_size(const fs::path& p) {
  const std::string b = [&] {
    std::ifstream in(p, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  }();
  if (b.size() < 24 || b.compare(1, 3, "PNG") != 0) return {0, 0};
  auto be32 = [&](size_t at) {
    int v = 0;
    for (size_t k = 0; k < 4; ++k) v = (v << 8) | static_cast<unsigned char>(b[at + k]);
    return v;
  };
  return {be32(16), be32(20)};
}

class StudyCli : public tissu::test::TempDirTest {
 protected:
  StudyCli() : TempDirTest("tissu_study_cli") {}

  Result run(const std::string& args) {
    return tissu::test::run_tissu_shell(args, dir_ / "stderr.txt", /*discard_stdout=*/true);
  }

  static std::string hard(const std::string& name) {
    return std::string(TISSU_SOURCE_DIR) + "/scenes/hard/" + name + ".json";
  }

  // About 50 triangles of silk hanging from two corners, 0.02 s.
  std::string tiny_scene() {
    const std::string path = (dir_ / "tiny.json").string();
    std::ofstream(path) << R"({
      "name": "tiny", "dt": 1e-4, "duration": 0.02, "integrator": "symplectic_euler",
      "cloth": {"mesh": {"generate": "rectangle", "size": [0.2, 0.2], "triangles": 50,
                         "irregular": true, "seed": 3},
                "material": "silk",
                "pins": [{"box": {"min": [-1, 0.099, -1], "max": [-0.099, 1, 1]}},
                         {"box": {"min": [0.099, 0.099, -1], "max": [1, 1, 1]}}]},
      "gravity": [0, 0, -9.81]
    })";
    return path;
  }

};

// The stiffest preset at 1/240 s with explicit Euler: far beyond its limit.
TEST_F(StudyCli, LinenBeyondTheExplicitLimitExitsThreeWithStepAndVertex) {
  const fs::path out = dir_ / "out";
  const Result r = run("run " + hard("linen_large_step") + " --set integrator=explicit_euler" +
                       " --out " + out.string() + " --quiet");
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_NE(r.err.find("diverged at step"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("vertex"), std::string::npos) << r.err;
  const Json report = Json::parse(read_text(out / "report.json"));
  EXPECT_EQ(report["status"], "diverged");
  EXPECT_GE(report["divergence"]["step"].get<int>(), 1);
  EXPECT_GE(report["divergence"]["vertex"].get<int>(), 0);
}

// Slivers with symplectic Euler at 50 times the scene step: the needles blow up.
TEST_F(StudyCli, SliversBeyondTheirLimitExitThree) {
  const fs::path out = dir_ / "out";
  const Result r = run("run " + hard("slivers") + " --set dt=1e-4 --set duration=0.05" +
                       " --out " + out.string() + " --quiet");
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_NE(r.err.find("diverged at step"), std::string::npos) << r.err;
  const Json report = Json::parse(read_text(out / "report.json"));
  EXPECT_GE(report["divergence"]["vertex"].get<int>(), 0);
}

TEST_F(StudyCli, StudyWritesCsvMarkdownAndPlot) {
  const fs::path out = dir_ / "study";
  const Result r = run("study " + tiny_scene() + " --out " + out.string() +
                       " --integrators symplectic_euler,backward_euler --dts 1e-4,2e-4" +
                       " --samples 0.01,0.02 --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string csv = read_text(out / "study.csv");
  int lines = 0;
  for (char c : csv) lines += c == '\n';
  EXPECT_EQ(lines, 1 + 4) << csv;  // header + 2 integrators x 2 steps
  EXPECT_NE(csv.find("rms_mm_t0.01"), std::string::npos) << csv;
  EXPECT_NE(csv.find("backward_euler,0.0002,"), std::string::npos) << csv;
  const std::string md = read_text(out / "study.md");
  EXPECT_NE(md.find("| integrator | dt (s) |"), std::string::npos);
  EXPECT_TRUE(md.find("**Converged:**") != std::string::npos ||
              md.find("**Not converged:**") != std::string::npos)
      << md;
  EXPECT_NE(md.find("![error against time](study.png)"), std::string::npos);
  EXPECT_EQ(png_size(out / "study.png"), std::make_pair(960, 640));
}

TEST_F(StudyCli, StabilityWritesTheLimitOfEachIntegrator) {
  const fs::path out = dir_ / "stability";
  const Result r = run("stability " + tiny_scene() + " --out " + out.string() +
                       " --integrators symplectic_euler,backward_euler --dt-max 4e-3 --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string csv = read_text(out / "stability.csv");
  EXPECT_NE(csv.find("tiny,symplectic_euler,"), std::string::npos) << csv;
  EXPECT_NE(csv.find("tiny,backward_euler,"), std::string::npos) << csv;
  const std::string md = read_text(out / "stability.md");
  EXPECT_NE(md.find("| scene | symplectic_euler | backward_euler |"), std::string::npos) << md;
}

TEST_F(StudyCli, BadOptionsAreBadInputAndWriteNothing) {
  const fs::path out = dir_ / "out";
  Result r = run("study " + tiny_scene() + " --integrators rk4 --out " + out.string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--integrators: unknown integrator \"rk4\""), std::string::npos) << r.err;
  r = run("study " + tiny_scene() + " --dts 1e-4,-1 --out " + out.string());
  EXPECT_EQ(r.exit_code, 2);
  r = run("study " + tiny_scene() + " --samples 5 --out " + out.string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("outside"), std::string::npos) << r.err;
  r = run("stability " + tiny_scene() + " --dt-min 1 --dt-max 0.1 --out " + out.string());
  EXPECT_EQ(r.exit_code, 2);
  r = run("stability --out " + out.string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_FALSE(fs::exists(out / "study.csv"));
  EXPECT_FALSE(fs::exists(out / "stability.csv"));
}

}  // namespace
