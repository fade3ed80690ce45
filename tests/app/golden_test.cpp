// Visual regression against golden frames, and determinism of whole runs.
//   Regenerate the goldens on purpose:  make golden
//   (runs this test with TISSU_UPDATE_GOLDEN=1, which rewrites tests/golden/*.png)
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>
#include <unistd.h>

#include "video/image.h"
#include "video/png_io.h"

namespace {

namespace fs = std::filesystem;
using tissu::Image;

// The tolerance of the visual regression (at most 0.5% of the pixels differing by more
// than 8/255, mean difference under 1/255), the one `tissu compare` applies by default.
const tissu::FrameTolerance kTolerance;

fs::path source_dir() { return fs::path(TISSU_SOURCE_DIR); }

fs::path scratch(const std::string& name) {
  const fs::path p = fs::temp_directory_path() / ("tissu_golden_" + std::to_string(getpid())) / name;
  fs::remove_all(p);
  fs::create_directories(p);
  return p;
}

// Renders the last frame of a scene with the tissu program into `out`; returns the PNG.
fs::path render_last_frame(const fs::path& scene, const fs::path& out, const std::string& env = "",
                           bool mp4 = false, const std::string& options = "") {
  const std::string command = env + " " + TISSU_BINARY + " render " + scene.string() + " --out " +
                              out.string() + (mp4 ? "" : " --no-mp4") + " --stills 1 --quiet " +
                              options;
  EXPECT_EQ(std::system(command.c_str()), 0) << command;
  for (const auto& entry : fs::directory_iterator(out / "stills")) return entry.path();
  return {};
}

std::string file_bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

class Golden : public ::testing::TestWithParam<std::string> {};

TEST_P(Golden, FrameMatchesWithinTolerance) {
  const std::string name = GetParam();
  const fs::path scene = source_dir() / "tests/golden/scenes" / (name + ".json");
  const fs::path golden = source_dir() / "tests/golden" / (name + ".png");
  const fs::path frame = render_last_frame(scene, scratch(name));
  ASSERT_FALSE(frame.empty());
  if (std::getenv("TISSU_UPDATE_GOLDEN")) {
    fs::copy_file(frame, golden, fs::copy_options::overwrite_existing);
    GTEST_SKIP() << "golden frame rewritten: " << golden;
  }
  ASSERT_TRUE(fs::exists(golden)) << golden << " is missing; run `make golden`";
  const Image expected = tissu::read_png(golden.string());
  const Image actual = tissu::read_png(frame.string());
  ASSERT_EQ(actual.width, expected.width);
  ASSERT_EQ(actual.height, expected.height);
  const tissu::ImageDiff diff = tissu::compare_images(expected, actual, kTolerance.threshold);
  if (!kTolerance.accepts(diff)) {
    const fs::path failures = source_dir() / "out/golden-failures";
    fs::create_directories(failures);
    const fs::path new_frame = failures / (name + ".new.png");
    const fs::path diff_image = failures / (name + ".diff.png");
    fs::copy_file(frame, new_frame, fs::copy_options::overwrite_existing);
    tissu::write_png(diff_image.string(), tissu::difference_image(expected, actual));
    ADD_FAILURE() << name << ": " << 100 * diff.fraction_over_threshold
                  << "% of pixels differ by more than " << kTolerance.threshold
                  << "/255, mean difference " << diff.mean_abs_diff << "/255; new frame "
                  << new_frame << ", difference " << diff_image;
  }
}

INSTANTIATE_TEST_SUITE_P(Scenes, Golden, ::testing::Values("sphere", "cylinder", "hanging"));

nlohmann::json frames_of(const fs::path& report) {
  std::ifstream in(report);
  return nlohmann::json::parse(in)["frames"];
}

// The same scene gives bit-identical simulation results, frames and video on every run and
// at any simulation and rasterizer thread count.
TEST(Determinism, BitIdenticalAtAnyThreadCount) {
  const fs::path scene = source_dir() / "tests/golden/scenes/sphere.json";
  const fs::path a = scratch("det_a"), b = scratch("det_b");
  // 6000 triangles, so that steps use 3 threads (2000 triangles per thread at least), with
  // a step below this finer mesh's stability limit.
  const std::string finer =
      " --set cloth.mesh.triangles=6000 --set dt=2.5e-5 --set duration=0.1";
  const fs::path frame_a =
      render_last_frame(scene, a, "LP_NUM_THREADS=1", /*mp4=*/true, "--threads 1" + finer);
  const fs::path frame_b =
      render_last_frame(scene, b, "LP_NUM_THREADS=4", /*mp4=*/true, "--threads 3" + finer);
  EXPECT_EQ(file_bytes(frame_a), file_bytes(frame_b));
  EXPECT_EQ(file_bytes(a / "golden_sphere.mp4"), file_bytes(b / "golden_sphere.mp4"));
  EXPECT_GT(file_bytes(a / "golden_sphere.mp4").size(), 1000u);
  EXPECT_EQ(frames_of(a / "report.json"), frames_of(b / "report.json"));
  // The report names the threads used: 3 asked for, at most the processors available.
  std::ifstream report_b(b / "report.json");
  const int used = nlohmann::json::parse(report_b)["threads"];
  EXPECT_EQ(used, std::min(3, static_cast<int>(std::max(1u, std::thread::hardware_concurrency()))));
}

}  // namespace
