// tissu figure: renders figure files (panels of scenes run to an iteration, with captions)
// into PNG images, and optionally each panel's run as an MP4. Everything is loaded and
// validated first: bad input writes nothing.
#include <filesystem>
#include <iostream>
#include <memory>

#include "app/cli.h"
#include "app/commands.h"
#include "app/figure_report.h"
#include "app/render_sink.h"
#include "app/report.h"
#include "core/error.h"
#include "figure/figure.h"
#include "view/scene_render_settings.h"
#include "physics/diagnostics.h"
#include "video/png_io.h"

namespace tissu {

namespace {

namespace fs = std::filesystem;

const char* kUsage =
    "usage: tissu figure FIGURE.json... [--out FILE.png | --out-dir DIR] [--mp4-dir DIR]\n"
    "                    [--caption-times] [--quiet]\n"
    "Runs every panel of a figure file to its iteration, draws it, and writes one PNG with\n"
    "the panels, a caption under each and the title, and beside it FILE.report.json with\n"
    "each panel's outcome and measured wall times. A panel that diverges shows its last\n"
    "good state and says where it diverged. The PNG is the same bits on every run.\n"
    "  --out FILE.png   the image (one figure only; default out/figures/<figure>.png)\n"
    "  --out-dir DIR    directory of the images, named after the figure files\n"
    "                   (default out/figures)\n"
    "  --mp4-dir DIR    also write each panel's run as DIR/<figure>_panel<N>.mp4\n"
    "  --caption-times  draw the measured wall time where a caption says {T} (else\n"
    "                   \"see report\"); the image then differs from run to run\n"
    "  --quiet          no progress lines\n"
    "The figure format is described in docs/paper.md.\n"
    "Exit codes: 0 ok (also when panels diverge), 1 output error, 2 bad input.\n";

struct FigureOptions {
  std::vector<std::string> figures;
  std::string out_file, out_dir, mp4_dir;
  bool quiet = false;
  bool caption_times = false;
};

bool parse_options(const std::vector<std::string>& args, FigureOptions& o) {
  const bool go =
      walk_arguments(args, "tissu figure", kUsage, [&](const std::string& a, const OptionValue& value) {
        if (a == "--out") {
          o.out_file = value();
        } else if (a == "--out-dir") {
          o.out_dir = value();
        } else if (a == "--mp4-dir") {
          o.mp4_dir = value();
        } else if (a == "--quiet") {
          o.quiet = true;
        } else if (a == "--caption-times") {
          o.caption_times = true;
        } else if (a.rfind("-", 0) == 0) {
          return false;
        } else {
          o.figures.push_back(a);
        }
        return true;
      });
  if (!go) return false;
  if (o.figures.empty()) throw UsageError("tissu figure: no figure file given (see tissu figure --help)");
  if (!o.out_file.empty() && o.figures.size() > 1) {
    throw UsageError("tissu figure: --out names one image; use --out-dir for several figures");
  }
  if (!o.out_file.empty() && !o.out_dir.empty()) {
    throw UsageError("tissu figure: give either --out or --out-dir");
  }
  if (o.out_dir.empty()) o.out_dir = "out/figures";
  return true;
}

// Writes each panel's run as an MP4 through the `tissu render` machinery.
class Mp4Panels : public PanelObserver {
 public:
  Mp4Panels(std::string dir, std::string stem, int width, int height)
      : dir_(std::move(dir)), stem_(std::move(stem)), width_(width), height_(height) {}

  long long begin(size_t index, const PanelSpec&, const Scene& scene) override {
    const RenderSettings settings = still_render_settings(scene, width_, height_);
    RenderOutputs outputs;
    path_ = (fs::path(dir_) / (stem_ + "_panel" + std::to_string(index + 1) + ".mp4")).string();
    outputs.mp4_path = path_;
    sink_ = std::make_unique<RenderSink>(settings, outputs);
    return steps_per_frame(scene.dt, frames_per_simulated_second(settings));
  }

  void frame(const Model& model, const State& state) override {
    sink_->frame(model, state, measure_frame(model, state));
  }

  void end(size_t, const PanelRun&) override {
    sink_->finish();
    sink_.reset();
    written_.push_back(path_);
  }

  void abort() noexcept {
    if (sink_) sink_->abort();
  }

  const std::vector<std::string>& written() const { return written_; }

 private:
  std::string dir_, stem_, path_;
  int width_, height_;
  std::unique_ptr<RenderSink> sink_;
  std::vector<std::string> written_;
};

std::string describe(const PanelOutcome& p) {
  std::string s = p.scene_name + " (" + std::to_string(p.triangles) + " triangles): ";
  if (p.divergence) {
    s += "diverged at iteration " + std::to_string(p.divergence->step) + " (" +
         p.divergence->reason + "), showing iteration " + std::to_string(p.shown);
  } else {
    s += std::to_string(p.shown) + " iterations";
  }
  char times[96];
  std::snprintf(times, sizeof times, "; simulation %.3f s, drawing %.3f s", p.simulate_seconds,
                p.render_seconds);
  return s + times;
}

}  // namespace

int command_figure(const std::vector<std::string>& args) {
  FigureOptions options;
  if (!parse_options(args, options)) return kExitOk;

  // Load and validate everything before running anything.
  std::vector<FigureSpec> figures;
  std::vector<std::vector<Scene>> scenes;
  for (const std::string& file : options.figures) {
    figures.push_back(load_figure(file));
    scenes.push_back(load_figure_scenes(figures.back()));
  }
  std::vector<std::string> outputs;
  for (const std::string& file : options.figures) {
    outputs.push_back(!options.out_file.empty()
                          ? options.out_file
                          : (fs::path(options.out_dir) / (fs::path(file).stem().string() + ".png"))
                                .string());
    const std::string parent = fs::path(outputs.back()).parent_path().string();
    prepare_output_dir(parent.empty() ? "." : parent);
  }
  if (!options.mp4_dir.empty()) prepare_output_dir(options.mp4_dir);

  for (size_t f = 0; f < figures.size(); ++f) {
    const FigureSpec& figure = figures[f];
    const std::string stem = fs::path(options.figures[f]).stem().string();
    std::unique_ptr<Mp4Panels> videos;
    if (!options.mp4_dir.empty()) {
      videos = std::make_unique<Mp4Panels>(options.mp4_dir, stem, figure.panel_width,
                                           figure.panel_height);
    }
    PanelProgress progress;
    if (!options.quiet) {
      progress = [&](size_t i, const PanelOutcome& p) {
        std::cerr << "tissu: " << stem << ": panel " << i + 1 << "/" << figure.panels.size()
                  << ": " << describe(p) << "\n";
      };
    }
    FigureResult result;
    try {
      result = render_figure(figure, scenes[f], videos.get(), progress, options.caption_times);
    } catch (...) {
      if (videos) videos->abort();
      throw;
    }
    write_png(outputs[f], result.image);
    const std::string report = figure_report_path(outputs[f]);
    write_text_file(report, make_figure_report(figure, result, outputs[f]).dump(1) + "\n");
    if (!options.quiet) {
      std::cerr << "tissu: figure: " << outputs[f] << " (" << result.image.width << " x "
                << result.image.height << ")\n";
      std::cerr << "tissu: report: " << report << "\n";
      if (videos) {
        for (const std::string& v : videos->written()) std::cerr << "tissu: video: " << v << "\n";
      }
    }
  }
  return kExitOk;
}

}  // namespace tissu
