#include "app/figure_report.h"

#include <filesystem>

#include "app/command_line.h"
#include "app/report.h"

namespace tissu {

nlohmann::ordered_json make_figure_report(const FigureSpec& figure, const FigureResult& result,
                                          const std::string& image_path) {
  nlohmann::ordered_json report;
  report["figure_file"] = figure.file;
  report["image"] = image_path;
  report["tissu"] = tissu_identity();
  report["command_line"] = command_line();
  nlohmann::ordered_json panels = nlohmann::ordered_json::array();
  for (const PanelOutcome& p : result.panels) {
    nlohmann::ordered_json panel;
    panel["scene"] = p.scene_name;
    panel["scene_file"] = p.scene_file;
    panel["triangles"] = p.triangles;
    panel["step_requested"] = p.requested;
    panel["step_shown"] = p.shown;
    panel["divergence"] = p.divergence ? nlohmann::ordered_json{{"step", p.divergence->step},
                                                                {"reason", p.divergence->reason}}
                                       : nlohmann::ordered_json(nullptr);
    panel["caption"] = p.caption;
    panel["wall_time_s"] = {{"simulate", p.simulate_seconds}, {"draw", p.render_seconds}};
    panels.push_back(panel);
  }
  report["panels"] = panels;
  report["units"] = {{"wall_time_s", "s"}};
  return report;
}

std::string figure_report_path(const std::string& image_path) {
  std::filesystem::path p(image_path);
  return p.replace_extension(".report.json").string();
}

}  // namespace tissu
