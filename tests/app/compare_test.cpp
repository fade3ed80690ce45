// `tissu compare` end to end: PNG files, directories of frames and MP4 files rendered by
// the tissu program itself; exit codes, per-frame lines and difference images.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>

#include "common/tissu_shell.h"
#include "video/image.h"
#include "video/png_io.h"

namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;
using tissu::Image;
using tissu::test::read_text;

// A smooth picture, 64x48.
Image gradient() {
  Image image(64, 48);
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      std::uint8_t* p = image.pixel(x, y);
      p[0] = std::uint8_t(x * 4), p[1] = std::uint8_t(y * 5), p[2] = 128;
    }
  }
  return image;
}

// `image` with a 10x10 square at (20, 10) painted white: 100 of 3072 pixels, 3.3%.
Image with_square(Image image) {
  for (int y = 10; y < 20; ++y) {
    for (int x = 20; x < 30; ++x) image.pixel(x, y)[0] = image.pixel(x, y)[1] = image.pixel(x, y)[2] = 255;
  }
  return image;
}

class Compare : public tissu::test::TempDirTest {
 protected:
  Compare() : TempDirTest("tissu_compare") {}

  struct Result {
    int exit_code;
    std::string out;  // stdout
    std::string err;  // stderr
  };

  Result compare(const std::string& args) {
    const fs::path out = dir_ / "stdout.txt";
    const tissu::test::ShellResult r =
        tissu::test::run_tissu_shell("compare " + args + " > " + out.string(), dir_ / "stderr.txt");
    return {r.exit_code, read_text(out), r.err};
  }

  std::string png(const std::string& name, const Image& image) {
    const fs::path path = dir_ / name;
    fs::create_directories(path.parent_path());
    tissu::write_png(path.string(), image);
    return path.string();
  }

  // Renders `scene` with the tissu program to DIR/<name>/fall.mp4.
  std::string render(const std::string& name, const Json& scene, const std::string& options = "") {
    const fs::path scene_file = dir_ / (name + ".json");
    std::ofstream(scene_file) << scene.dump(2);
    const fs::path out = dir_ / name;
    const tissu::test::ShellResult r = tissu::test::run_tissu_shell(
        "render " + scene_file.string() + " --out " + out.string() + " --quiet " + options,
        dir_ / "render_err.txt");
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return (out / "fall.mp4").string();
  }

  // A small sheet falling slowly (it stays in view) for 0.3 s: 10 frames of 64x48 pixels.
  static Json tiny_scene() {
    return Json::parse(R"({
      "name": "fall", "dt": 0.004, "duration": 0.3, "integrator": "backward_euler",
      "cloth": {"mesh": {"generate": "rectangle", "size": [0.2, 0.2], "triangles": 50,
                         "irregular": true, "seed": 3},
                "material": "silk"},
      "gravity": [0, 0, -1],
      "render": {"width": 64, "height": 48, "msaa": 1, "fps": 30}
    })");
  }
};

TEST_F(Compare, IdenticalPngsExitZero) {
  const std::string a = png("a.png", gradient()), b = png("b.png", gradient());
  const Result r = compare(a + " " + b);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err, "");
  EXPECT_NE(r.out.find("a.png: PSNR inf dB, 0.000% of pixels over 8, mean difference 0.00: ok\n"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("1 frame compared, within tolerance\n"), std::string::npos) << r.out;
}

TEST_F(Compare, ChangedRegionExitsOneAndWritesADifferenceImage) {
  const std::string a = png("a.png", gradient()), b = png("b.png", with_square(gradient()));
  const fs::path diff_dir = dir_ / "diffs" / "new";
  const Result r = compare(a + " " + b + " --diff " + diff_dir.string());
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.out.find("a.png: PSNR "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("3.255% of pixels over 8"), std::string::npos) << r.out;  // 100 of 3072
  EXPECT_NE(r.out.find(": DIFFERS, difference image " + (diff_dir / "a.diff.png").string() + "\n"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("1 of 1 frame differs beyond tolerance: a.png\n"), std::string::npos) << r.out;
  // The difference image is |a - b| x 8: black outside the square, bright inside it.
  const Image diff = tissu::read_png((diff_dir / "a.diff.png").string());
  EXPECT_EQ(diff.rgb, tissu::difference_image(gradient(), with_square(gradient())).rgb);
  EXPECT_EQ(diff.pixel(0, 0)[0], 0);
  EXPECT_EQ(diff.pixel(25, 15)[2], 255);
  EXPECT_FALSE(fs::exists(diff_dir / ".a.diff.png.partial"));
}

TEST_F(Compare, ThresholdAndToleranceOptionsLoosenTheRule) {
  Image slightly = gradient();
  for (int x = 0; x < 64; ++x) slightly.pixel(x, 0)[2] += 5;  // one row, 5 over
  const std::string a = png("a.png", gradient()), b = png("b.png", slightly);
  EXPECT_EQ(compare(a + " " + b).exit_code, 0);  // under the default threshold of 8
  EXPECT_EQ(compare(a + " " + b + " --threshold 4").exit_code, 1);  // 2.1% over 4
  EXPECT_EQ(compare(a + " " + b + " --threshold 4 --tolerance 0.03").exit_code, 0);
}

TEST_F(Compare, DirectoriesWithAMissingFrameExitOneNamingIt) {
  for (const char* side : {"a", "b"}) {
    png(std::string(side) + "/frame_000000.png", gradient());
    png(std::string(side) + "/frame_000001.png", gradient());
  }
  png("a/frame_000002.png", gradient());
  std::ofstream(dir_ / "b" / "notes.txt") << "not a frame\n";  // ignored
  const fs::path a = dir_ / "a", b = dir_ / "b";
  const Result r = compare(a.string() + " " + b.string() + " --diff " + (dir_ / "d").string());
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.out.find("frame_000000.png: PSNR inf dB"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("frame_000002.png: only in " + a.string() + ": DIFFERS\n"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("1 of 3 frames differs beyond tolerance: frame_000002.png\n"),
            std::string::npos)
      << r.out;
  EXPECT_FALSE(fs::exists(dir_ / "d")) << "no difference image, so no directory left";
}

TEST_F(Compare, TheLastLineNamesTwentyDifferingFramesAndCountsTheRest) {
  for (int i = 0; i < 23; ++i) png("a/frame_" + std::to_string(100 + i) + ".png", Image(2, 2));
  png("b/frame_100.png", Image(2, 2));
  const Result r = compare((dir_ / "a").string() + " " + (dir_ / "b").string());
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.out.find("22 of 23 frames differ beyond tolerance: frame_101.png, frame_102.png,"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find(", frame_120.png and 2 more\n"), std::string::npos) << r.out;
}

TEST_F(Compare, DirectoriesOfEqualFramesExitZero) {
  for (const char* side : {"a", "b"}) {
    png(std::string(side) + "/frame_000000.png", gradient());
    png(std::string(side) + "/frame_000001.png", with_square(gradient()));
  }
  const Result r = compare((dir_ / "a").string() + " " + (dir_ / "b").string());
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("2 frames compared, all within tolerance\n"), std::string::npos) << r.out;
}

TEST_F(Compare, Mp4sOfTheSameSceneAreEqualAndOfAChangedSceneDiffer) {
  const std::string first = render("first", tiny_scene());
  const std::string again = render("again", tiny_scene());
  Json changed = tiny_scene();
  changed["render"]["cloth"] = {{"front_color", {0.1, 0.3, 0.9}}, {"back_color", {0.1, 0.8, 0.2}}};
  const std::string blue = render("blue", changed);

  Result r = compare(first + " " + again);
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("frame 9: PSNR inf dB"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("10 frames compared, all within tolerance\n"), std::string::npos) << r.out;

  const fs::path diffs = dir_ / "diffs";
  r = compare(first + " " + blue + " --diff " + diffs.string());
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  EXPECT_NE(r.out.find("10 of 10 frames differ beyond tolerance: frame 0, frame 1,"),
            std::string::npos)
      << r.out;
  EXPECT_TRUE(fs::exists(diffs / "frame_000000.diff.png"));
  EXPECT_TRUE(fs::exists(diffs / "frame_000009.diff.png"));
}

// The frames past the shorter video differ. (So do the shared ones here: x264's rate
// control looks ahead, so a video cut after 7 frames encodes even frame 0 differently, by
// about 2 of 255 on average, although the rendered frames are the same bits.)
TEST_F(Compare, Mp4sOfDifferentLengthsDiffer) {
  const std::string full = render("full", tiny_scene());
  const std::string cut = render("cut", tiny_scene(), "--frames 7");
  const Result r = compare(full + " " + cut);
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  EXPECT_NE(r.out.find("frame 6: PSNR "), std::string::npos) << r.out;
  for (const char* frame : {"frame 7", "frame 8", "frame 9"}) {
    EXPECT_NE(r.out.find(frame + (": only in " + full + ": DIFFERS\n")), std::string::npos) << r.out;
  }
  EXPECT_EQ(r.out.find("frame 10"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(full + " has 10 frames, " + cut + " has 7\n"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("frame 7, frame 8, frame 9\n"), std::string::npos) << r.out;
}

TEST_F(Compare, MissingFileExitsTwoWithOneLine) {
  const std::string a = png("a.png", gradient());
  const std::string missing = (dir_ / "missing.png").string();
  const Result r = compare(a + " " + missing);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err, "tissu: " + missing + ": cannot read: No such file or directory\n");
  EXPECT_EQ(r.out, "");
}

TEST_F(Compare, UnreadableInputExitsTwoNamingIt) {
  const std::string a = png("a.png", gradient());
  const std::string text = (dir_ / "text.png").string();
  std::ofstream(text) << "not a PNG\n";
  Result r = compare(a + " " + text);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err.rfind("tissu: " + text + ": not a readable PNG: ", 0), 0u) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;

  const std::string video = (dir_ / "text.mp4").string();
  std::ofstream(video) << "not a video\n";
  r = compare(video + " " + video);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err.rfind("tissu: " + video + ": ", 0), 0u) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
}

TEST_F(Compare, UsageErrorsExitTwo) {
  const std::string a = png("a.png", gradient());
  fs::create_directories(dir_ / "frames");
  png("frames/frame_000000.png", gradient());
  Result r = compare(a);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err, "tissu: tissu compare: expected two inputs A and B (see tissu compare --help)\n");
  r = compare(a + " " + (dir_ / "frames").string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err, "tissu: tissu compare: " + a + " is a PNG file but " + (dir_ / "frames").string() +
                       " is a directory; compare two PNG files, two directories of PNG frames or "
                       "two MP4 files\n");
  r = compare(a + " " + a + " --threshold 300");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err, "tissu: --threshold: expected at most 255, got 300\n");
  r = compare(a + " " + a + " --tolerance 2");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err, "tissu: --tolerance: expected a number from 0 to 1, got \"2\"\n");
  r = compare(a + " " + a + " --fuzzy");
  EXPECT_EQ(r.exit_code, 2);
  std::ofstream(dir_ / "notes.txt") << "x";
  r = compare((dir_ / "notes.txt").string() + " " + a);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err, "tissu: " + (dir_ / "notes.txt").string() +
                       ": not a PNG file, an MP4 file or a directory of PNG frames\n");
  fs::create_directories(dir_ / "empty");
  r = compare((dir_ / "empty").string() + " " + (dir_ / "frames").string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err, "tissu: " + (dir_ / "empty").string() + ": no PNG frames in directory\n");
}

TEST_F(Compare, DiffDirectoryThatCannotBeCreatedExitsTwo) {
  const std::string a = png("a.png", gradient()), b = png("b.png", with_square(gradient()));
  std::ofstream(dir_ / "file") << "x";
  const Result r = compare(a + " " + b + " --diff " + (dir_ / "file" / "sub").string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("cannot create output directory"), std::string::npos) << r.err;
}

TEST_F(Compare, FramesOfDifferentSizesDiffer) {
  const std::string a = png("a.png", gradient()), b = png("b.png", Image(32, 24));
  const Result r = compare(a + " " + b + " --diff " + (dir_ / "d").string());
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.out.find("a.png: 64x48 in " + a + ", 32x24 in " + b + ": DIFFERS\n"), std::string::npos)
      << r.out;
  EXPECT_FALSE(fs::exists(dir_ / "d"));
}

// A full disk while writing a difference image (its temporary name is a link to /dev/full):
// the comparison is unfinished, so exit 2 with the reason, and no difference image.
TEST_F(Compare, DifferenceImageThatCannotBeWrittenExitsTwo) {
  const std::string a = png("a.png", gradient()), b = png("b.png", with_square(gradient()));
  fs::create_directories(dir_ / "d");
  fs::create_symlink("/dev/full", dir_ / "d" / ".a.diff.png.partial");
  const Result r = compare(a + " " + b + " --diff " + (dir_ / "d").string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err, "tissu: " + (dir_ / "d" / "a.diff.png").string() +
                       ": cannot write PNG: No space left on device\n");
  EXPECT_FALSE(fs::exists(dir_ / "d" / "a.diff.png"));
}

TEST_F(Compare, HelpNamesEveryOption) {
  const Result r = compare("--help");
  EXPECT_EQ(r.exit_code, 0);
  for (const char* option : {"--threshold", "--tolerance", "--diff", "Exit codes"}) {
    EXPECT_NE(r.out.find(option), std::string::npos) << option;
  }
}

}  // namespace
