// Figure files: a list of panels (a scene, overrides, the iteration to show, a caption
// template) and a layout (columns, panel size in pixels, title). docs/paper.md documents
// the format. Reading is strict: unknown keys, wrong types and bad values are InputError
// naming the JSON path ("panels[1].step: must be >= 0, got -5").
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "scene/json_reader.h"

namespace tissu {

struct PanelSpec {
  std::string path;   // JSON path of the panel in its figure file ("panels[1]"), for messages
  std::string scene;  // scene file, relative to the working directory (resolved from the figure)
  // Dotted scene keys and their values, applied in order like `--set`; null removes the key
  // (e.g. "position_correction": null runs the scene without correction).
  std::vector<std::pair<std::string, Json>> overrides;
  long long step = 0;   // iteration shown
  std::string caption;  // template with {placeholders}, see caption_placeholders()
};

struct FigureSpec {
  std::string file;   // figure file ("" when parsed from memory)
  std::string title;  // drawn under the panels; may be empty
  int columns = 1;
  int panel_width = 640, panel_height = 480;  // pixels, even
  int font_px = 0;    // caption text height in pixels; 0 = from the panel height
  std::vector<PanelSpec> panels;
};

// Validates a figure document. Scene paths are resolved relative to `file`'s directory
// (and must exist). Throws InputError "<json path>: <problem>".
FigureSpec parse_figure(const Json& doc, const std::string& file);

// Reads (JSON with // comments) and validates a figure file; errors start with the file name.
FigureSpec load_figure(const std::string& file);

// Values a caption template can show. Every placeholder is replaced; {{ and }} give braces.
struct CaptionValues {
  std::string name;        // scene name
  long long triangles = 0;
  long long vertices = 0;
  long long step = 0;      // iteration shown
  // Wall time measured for simulating the panel, s; unset (drawn as "see report") unless
  // times are asked for in the image (tissu figure --caption-times).
  std::optional<double> wall_seconds;
  double time = 0;         // simulated time of the state shown, s
  std::string integrator;
  std::string material;
  double dt = 0;           // s
  bool correction = false; // position correction on
};

// The placeholders and what they show, in the order docs list them.
const std::vector<std::pair<std::string, std::string>>& caption_placeholders();

// Throws InputError "<path>: unknown placeholder {x} ..." for a bad template.
void check_caption_template(const std::string& text, const std::string& path);

std::string expand_caption(const std::string& text, const CaptionValues& values);

}  // namespace tissu
