// Figure files (strict validation naming JSON paths), panel runs (divergence shows the
// last good state), composition (size, caption text), the tissu figure command, and
// golden frames of some paper panels.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <sys/wait.h>
#include <unistd.h>

#include "common/tissu_shell.h"
#include "figure/compose.h"
#include "figure/figure.h"
#include "physics/materials.h"
#include "video/image.h"
#include "video/png_io.h"

namespace tissu {
namespace {

namespace fs = std::filesystem;

// A 0.3 m x 0.2 m sheet of about 50 triangles held at two corners.
Json tiny_scene() {
  return Json::parse(R"({
    "name": "tiny", "dt": 1e-4, "steps": 10, "integrator": "symplectic_euler",
    "cloth": {"mesh": {"generate": "rectangle", "size": [0.3, 0.2], "triangles": 50,
                       "irregular": true, "seed": 1},
              "material": "silk",
              "pins": [{"box": {"min": [-0.16, 0.09, -1], "max": [-0.14, 0.11, 1]}},
                       {"box": {"min": [0.14, 0.09, -1], "max": [0.16, 0.11, 1]}}]},
    "gravity": [0, 0, -9.81],
    "render": {"msaa": 1, "camera": {"eye": [0.2, -0.6, 0.3], "target": [0, 0, -0.03]}}
  })");
}

class FigureTest : public tissu::test::TempDirTest {
 protected:
  FigureTest() : TempDirTest("tissu_figure") {}

  void SetUp() override {
    TempDirTest::SetUp();
    std::ofstream(dir_ / "tiny.json") << tiny_scene().dump(2);
  }

  std::string figure_file() const { return (dir_ / "figure.json").string(); }

  static Json two_panels() {
    return Json::parse(R"({
      "title": "Two tiny panels",
      "columns": 2, "panel_size": [160, 120], "font_size": 12,
      "panels": [
        {"scene": "tiny.json", "step": 5, "caption": "{name} : {triangles} triangles, T = {T}"},
        {"scene": "tiny.json", "overrides": {"integrator": "benameur_djedi"}, "step": 10,
         "caption": "{integrator}, {step} iterations"}
      ]
    })");
  }

  // The message of the InputError parse_figure throws for `doc`.
  std::string error_of(const Json& doc) {
    try {
      parse_figure(doc, figure_file());
    } catch (const InputError& e) {
      return e.what();
    }
    return "(no error)";
  }
};

TEST_F(FigureTest, ParsesPanelsAndResolvesScenesFromTheFigureFile) {
  const FigureSpec fig = parse_figure(two_panels(), figure_file());
  ASSERT_EQ(fig.panels.size(), 2u);
  EXPECT_EQ(fig.columns, 2);
  EXPECT_EQ(fig.panel_width, 160);
  EXPECT_EQ(fig.panel_height, 120);
  EXPECT_EQ(fig.title, "Two tiny panels");
  EXPECT_EQ(fs::path(fig.panels[0].scene), (dir_ / "tiny.json").lexically_normal());
  EXPECT_EQ(fig.panels[1].step, 10);
  ASSERT_EQ(fig.panels[1].overrides.size(), 1u);
  EXPECT_EQ(fig.panels[1].overrides[0].first, "integrator");
}

TEST_F(FigureTest, ValidationErrorsNameTheJsonPath) {
  Json doc = two_panels();
  doc["panells"] = doc["panels"];
  doc.erase("panels");
  EXPECT_EQ(error_of(doc), "panels: is required");

  doc = two_panels();
  doc["titel"] = "x";
  EXPECT_EQ(error_of(doc), "titel: unknown key (did you mean \"title\"?)");

  doc = two_panels();
  doc["panels"][1]["stepp"] = 3;
  EXPECT_EQ(error_of(doc), "panels[1].stepp: unknown key (did you mean \"panels[1].step\"?)");

  doc = two_panels();
  doc["panels"][1]["step"] = -5;
  EXPECT_EQ(error_of(doc).rfind("panels[1].step: ", 0), 0u) << error_of(doc);

  doc = two_panels();
  doc["panels"][0]["step"] = 2.5;
  EXPECT_EQ(error_of(doc), "panels[0].step: must be an integer, got 2.5");

  doc = two_panels();
  doc["panels"][0]["step"] = "last";
  EXPECT_EQ(error_of(doc).rfind("panels[0].step: ", 0), 0u) << error_of(doc);

  doc = two_panels();
  doc["panels"][0].erase("step");
  EXPECT_EQ(error_of(doc), "panels[0].step: is required");

  doc = two_panels();
  doc["panels"] = Json::array();
  EXPECT_EQ(error_of(doc), "panels: must list at least one panel");

  doc = two_panels();
  doc["panels"][0]["caption"] = "T = {time}";
  EXPECT_EQ(error_of(doc).rfind("panels[0].caption: unknown placeholder {time}", 0), 0u)
      << error_of(doc);

  doc = two_panels();
  doc["panels"][1]["scene"] = "missing.json";
  EXPECT_EQ(error_of(doc).rfind("panels[1].scene: no such scene file", 0), 0u) << error_of(doc);

  doc = two_panels();
  doc["panel_size"] = {161, 120};
  EXPECT_EQ(error_of(doc), "panel_size[0]: must be an even integer, got 161");

  doc = two_panels();
  doc["columns"] = 3;
  EXPECT_EQ(error_of(doc).rfind("columns: ", 0), 0u) << error_of(doc);

  doc = two_panels();
  doc["panels"][0]["overrides"] = Json::array({"dt=1"});
  EXPECT_EQ(error_of(doc).rfind("panels[0].overrides: must be an object", 0), 0u)
      << error_of(doc);
}

TEST_F(FigureTest, BadOverrideIsNamedWhenTheScenesAreLoaded) {
  Json doc = two_panels();
  doc["panels"][1]["overrides"]["dt"] = -1;
  std::ofstream(figure_file()) << doc.dump();
  const FigureSpec fig = load_figure(figure_file());
  try {
    load_figure_scenes(fig);
    FAIL() << "expected an error";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_EQ(m.rfind(figure_file() + ": panels[1].overrides.dt: ", 0), 0u) << m;
    EXPECT_NE(m.find("dt: must be in (0, 1], got -1"), std::string::npos) << m;
  }
}

TEST_F(FigureTest, NullOverrideRemovesASceneBlock) {
  Json doc = tiny_scene();
  doc["position_correction"] = {{"threshold", 1e-3}, {"iterations", 2}};
  apply_panel_override(doc, "position_correction", Json());
  EXPECT_FALSE(doc.contains("position_correction"));
  apply_panel_override(doc, "wind", Json());  // absent: nothing to do
  apply_panel_override(doc, "cloth.material", "cotton");
  EXPECT_EQ(doc["cloth"]["material"], "cotton");
}

TEST_F(FigureTest, CaptionTemplates) {
  CaptionValues v;
  v.name = "Tissu 1";
  v.triangles = 4847;
  v.wall_seconds = 1.2345;
  v.step = 31;
  v.time = 0.26;
  v.correction = true;
  EXPECT_EQ(expand_caption("{name} : {triangles} triangles, T = {T}", v),
            "Tissu 1 : 4847 triangles, T = 1.234 s");  // 1.2345 rounds to even in printf
  EXPECT_EQ(expand_caption("{step} iterations, t = {t}, {correction} {{x}}", v),
            "31 iterations, t = 0.260 s, with position correction {x}");
  v.wall_seconds.reset();  // times left out of the image
  EXPECT_EQ(expand_caption("T = {T}", v), "T = see report");
  EXPECT_THROW(check_caption_template("open {name", "c"), InputError);
  EXPECT_THROW(check_caption_template("close }", "c"), InputError);
}

// Fraction of dark (text) pixels in a rectangle of the page.
double dark_fraction(const Image& img, int x0, int y0, int x1, int y1) {
  int dark = 0, all = 0;
  for (int y = y0; y < y1; ++y) {
    for (int x = x0; x < x1; ++x) {
      const uint8_t* p = img.pixel(x, y);
      dark += (p[0] < 128 && p[1] < 128 && p[2] < 128);
      ++all;
    }
  }
  return all ? static_cast<double>(dark) / all : 0.0;
}

TEST_F(FigureTest, ComposesPanelsWithCaptionsAndTitle) {
  std::ofstream(figure_file()) << two_panels().dump();
  const FigureSpec fig = load_figure(figure_file());
  const FigureResult result = render_figure(fig, load_figure_scenes(fig));
  ASSERT_EQ(result.panels.size(), 2u);
  EXPECT_EQ(result.panels[0].shown, 5);
  EXPECT_EQ(result.panels[1].shown, 10);
  EXPECT_FALSE(result.panels[0].divergence);
  EXPECT_GT(result.panels[0].simulate_seconds, 0.0);
  EXPECT_EQ(result.panels[0].caption.rfind("tiny : 50 triangles, T = ", 0), 0u)
      << result.panels[0].caption;
  EXPECT_EQ(result.panels[1].caption, "benameur_djedi, 10 iterations");

  // Layout: margins of font_size (12 px) around and between two 160 px panels.
  const Image& img = result.image;
  EXPECT_EQ(img.width, 12 + 160 + 12 + 160 + 12);
  EXPECT_EQ(img.width % 2, 0);
  EXPECT_EQ(img.height % 2, 0);
  // Panels, one caption line each, the title: at least 2 margins + 120 + 2 lines of 12 px.
  EXPECT_GE(img.height, 12 + 120 + 2 * 12 + 12);
  EXPECT_LE(img.height, 12 + 120 + 6 + 2 * 20 + 6 + 20 + 12);
  // The panel area is the rendered picture (background gradient, not the white page).
  const uint8_t* inside = img.pixel(12 + 80, 12 + 5);
  EXPECT_LT(inside[0] + inside[1] + inside[2], 3 * 200);
  // Caption text under each panel: dark pixels in the strip under the panel.
  const int strip_top = 12 + 120 + 1, strip_bottom = strip_top + 24;
  EXPECT_GT(dark_fraction(img, 12, strip_top, 12 + 160, strip_bottom), 0.02);
  EXPECT_GT(dark_fraction(img, 12 + 160 + 12, strip_top, 12 + 2 * 160 + 12, strip_bottom), 0.02);
  // The title at the bottom, and white margins.
  EXPECT_GT(dark_fraction(img, 0, img.height - 34, img.width, img.height), 0.01);
  EXPECT_EQ(dark_fraction(img, 0, 0, img.width, 10), 0.0);
  const uint8_t* corner = img.pixel(2, 2);
  EXPECT_EQ(corner[0] + corner[1] + corner[2], 3 * 255);
}

TEST_F(FigureTest, DivergingPanelShowsLastGoodStateAndSaysWhere) {
  Json doc = two_panels();
  // Explicit Euler at 100 times the stable step of this mesh: diverges within a few steps.
  doc["panels"][1]["overrides"] = {{"integrator", "explicit_euler"}, {"dt", 0.01},
                                   {"cloth.material", "cotton"}};
  doc["panels"][1]["step"] = 500;
  doc["panels"][1]["caption"] = "Without position correction\n{step} iterations";
  std::ofstream(figure_file()) << doc.dump();
  const FigureSpec fig = load_figure(figure_file());
  const FigureResult result = render_figure(fig, load_figure_scenes(fig));
  const PanelOutcome& p = result.panels[1];
  ASSERT_TRUE(p.divergence.has_value());
  EXPECT_LT(p.divergence->step, 500);
  EXPECT_EQ(p.shown, p.divergence->step - 1);
  EXPECT_EQ(p.caption, "Without position correction\n" + std::to_string(p.shown) +
                           " iterations\ndiverged at iteration " +
                           std::to_string(p.divergence->step));
  EXPECT_NE(p.caption.find("diverged"), std::string::npos);
}

TEST_F(FigureTest, LastGoodStateIsFiniteAndFramesReachIt) {
  Scene scene = parse_scene(tiny_scene(), (dir_ / "tiny.json").string());
  scene.integrator = Integrator::ExplicitEuler;
  scene.dt = 0.01;
  scene.material = *material_preset("cotton");
  long long frames = 0, last_frame_step = -1;
  const PanelRun run = run_panel(scene, 500, 1, [&](const Model&, const State& s) {
    ++frames;
    last_frame_step = s.step;
  });
  ASSERT_TRUE(run.diverged());
  for (const Vec3& x : run.sim.state.x) EXPECT_TRUE(x.allFinite());
  EXPECT_EQ(last_frame_step, run.sim.state.step);
  EXPECT_EQ(frames, run.sim.state.step + 1);  // iterations 0 .. last good
}

// The tissu program: bad input exits 2 naming the figure path and writes nothing.
int run_tissu(const std::string& args, const fs::path& err_file) {
  return tissu::test::run_tissu_shell(args, err_file).exit_code;
}

using tissu::test::read_text;

TEST_F(FigureTest, CommandWritesTheImageOrRejectsBadInput) {
  Json doc = two_panels();
  std::ofstream(figure_file()) << doc.dump();
  const fs::path out = dir_ / "out" / "fig.png";
  ASSERT_EQ(run_tissu("figure " + figure_file() + " --out " + out.string() + " --quiet",
                      dir_ / "err.txt"),
            0)
      << read_text(dir_ / "err.txt");
  const Image img = read_png(out.string());
  EXPECT_EQ(img.width, 12 + 160 + 12 + 160 + 12);

  doc["panels"][0]["step"] = -1;
  std::ofstream(figure_file()) << doc.dump();
  const fs::path out2 = dir_ / "out2" / "fig.png";
  EXPECT_EQ(run_tissu("figure " + figure_file() + " --out " + out2.string(), dir_ / "err.txt"), 2);
  EXPECT_EQ(read_text(dir_ / "err.txt").rfind("tissu: " + figure_file() + ": panels[0].step: ", 0),
            0u)
      << read_text(dir_ / "err.txt");
  EXPECT_FALSE(fs::exists(out2.parent_path()));
}

// The image leaves the measured wall times out (the report beside it has them), so two
// runs give the same bytes; --caption-times draws them.
TEST_F(FigureTest, CommandImageIsTheSameBitsOnEveryRun) {
  Json doc = two_panels();
  doc["panels"][0]["step"] = 3000;  // milliseconds of simulation: {T} would differ
  std::ofstream(figure_file()) << doc.dump();
  const fs::path first = dir_ / "a" / "fig.png", second = dir_ / "b" / "fig.png";
  for (const fs::path& out : {first, second}) {
    ASSERT_EQ(run_tissu("figure " + figure_file() + " --out " + out.string() + " --quiet",
                        dir_ / "err.txt"),
              0)
        << read_text(dir_ / "err.txt");
  }
  EXPECT_GT(read_text(first).size(), 0u);
  EXPECT_TRUE(read_text(first) == read_text(second)) << "the PNGs differ";

  const Json report = Json::parse(read_text(dir_ / "a" / "fig.report.json"));
  ASSERT_EQ(report["panels"].size(), 2u);
  EXPECT_EQ(report["panels"][0]["caption"], "tiny : 50 triangles, T = see report");
  EXPECT_EQ(report["panels"][0]["step_shown"], 3000);
  EXPECT_GT(report["panels"][0]["wall_time_s"]["simulate"].get<double>(), 0.0);
  EXPECT_EQ(report["panels"][1]["caption"], "benameur_djedi, 10 iterations");

  const fs::path timed = dir_ / "c" / "fig.png";
  ASSERT_EQ(run_tissu("figure " + figure_file() + " --out " + timed.string() +
                          " --caption-times --quiet",
                      dir_ / "err.txt"),
            0)
      << read_text(dir_ / "err.txt");
  const Json timed_report = Json::parse(read_text(dir_ / "c" / "fig.report.json"));
  const std::string caption = timed_report["panels"][0]["caption"];
  EXPECT_EQ(caption.rfind("tiny : 50 triangles, T = ", 0), 0u) << caption;
  EXPECT_EQ(caption.find("see report"), std::string::npos) << caption;
  EXPECT_EQ(caption.back(), 's') << caption;
}

// Golden frames: small versions of paper panels, rendered again and compared.
// TISSU_UPDATE_GOLDEN=1 rewrites them.
struct GoldenPanel {
  const char* golden;  // tests/golden/<golden>.png
  const char* figure;  // figures/<figure>.json
  int panel;           // index in the figure
};

void PrintTo(const GoldenPanel& g, std::ostream* os) { *os << g.golden; }

class PaperGolden : public ::testing::TestWithParam<GoldenPanel> {};

TEST_P(PaperGolden, PanelMatchesGoldenFrame) {
  const GoldenPanel g = GetParam();
  const fs::path source = TISSU_SOURCE_DIR;
  const FigureSpec fig = load_figure((source / "figures" / (std::string(g.figure) + ".json")).string());
  const PanelSpec& spec = fig.panels.at(g.panel);
  const Scene scene = load_panel_scene(spec, fig.file);
  const PanelRun run = run_panel(scene, spec.step);
  const Image frame = render_panel(scene, run, 320, 240);
  const fs::path golden = source / "tests" / "golden" / (std::string(g.golden) + ".png");
  if (std::getenv("TISSU_UPDATE_GOLDEN")) {
    write_png(golden.string(), frame);
    GTEST_SKIP() << "wrote " << golden;
  }
  ASSERT_TRUE(fs::exists(golden)) << golden << " is missing; TISSU_UPDATE_GOLDEN=1 writes it";
  const Image expected = read_png(golden.string());
  ASSERT_EQ(expected.width, frame.width);
  ASSERT_EQ(expected.height, frame.height);
  // The golden-frame rule: at most 0.5 % of the pixels differ by more than 8/255, mean
  // under 1/255.
  const FrameTolerance tolerance;
  const ImageDiff d = compare_images(expected, frame, tolerance.threshold);
  if (!tolerance.accepts(d)) {
    const fs::path out = TISSU_TEST_OUT_DIR;
    fs::create_directories(out);
    const fs::path got = out / (std::string(g.golden) + ".new.png");
    const fs::path diff = out / (std::string(g.golden) + ".diff.png");
    write_png(got.string(), frame);
    write_png(diff.string(), difference_image(expected, frame));
    ADD_FAILURE() << g.golden << ": " << 100 * d.fraction_over_threshold
                  << " % of pixels differ by more than 8/255 (at most 0.5 % allowed), mean "
                  << d.mean_abs_diff << "/255 (under 1 allowed), largest " << d.max_diff
                  << "/255. New frame: " << got << ", difference x8: " << diff
                  << " (golden: " << golden << ")";
  }
}

INSTANTIATE_TEST_SUITE_P(
    Panels, PaperGolden,
    ::testing::Values(GoldenPanel{"paper_fig03_tissu2", "fig03", 1},
                      GoldenPanel{"paper_fig06_corrected", "fig06", 1},
                      GoldenPanel{"paper_fig11_first", "fig11", 0}),
    [](const ::testing::TestParamInfo<GoldenPanel>& info) { return std::string(info.param.golden); });

}  // namespace
}  // namespace tissu
