#include "figure/figure.h"

#include <chrono>

#include "figure/compose.h"

namespace tissu {

std::vector<Scene> load_figure_scenes(const FigureSpec& figure) {
  std::vector<Scene> scenes;
  for (const PanelSpec& panel : figure.panels) scenes.push_back(load_panel_scene(panel, figure.file));
  return scenes;
}

FigureResult render_figure(const FigureSpec& figure, const std::vector<Scene>& scenes,
                           PanelObserver* observer, const PanelProgress& progress,
                           bool caption_times) {
  FigureResult result;
  std::vector<Image> images;
  std::vector<std::string> captions;
  for (size_t i = 0; i < figure.panels.size(); ++i) {
    const PanelSpec& spec = figure.panels[i];
    const Scene& scene = scenes.at(i);
    long long frame_every = 0;
    FrameCallback on_frame;
    if (observer) {
      frame_every = observer->begin(i, spec, scene);
      on_frame = [observer](const Model& m, const State& s) { observer->frame(m, s); };
    }
    const PanelRun run = run_panel(scene, spec.step, frame_every, on_frame);
    if (observer) observer->end(i, run);

    const auto t0 = std::chrono::steady_clock::now();
    images.push_back(render_panel(scene, run, figure.panel_width, figure.panel_height));
    PanelOutcome out;
    out.render_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    out.scene_name = scene.name;
    out.triangles = run.sim.model.num_triangles();
    out.requested = run.requested;
    out.shown = run.sim.state.step;
    out.divergence = run.divergence;
    out.simulate_seconds = run.simulate_seconds;
    out.scene_file = spec.scene;
    out.caption = panel_caption(spec.caption, scene, run, caption_times);
    captions.push_back(out.caption);
    if (progress) progress(i, out);
    result.panels.push_back(std::move(out));
  }
  FigureLayout layout;
  layout.columns = figure.columns;
  layout.font_px = figure.font_px;
  layout.title = figure.title;
  result.image = compose_figure(images, captions, layout);
  return result;
}

}  // namespace tissu
