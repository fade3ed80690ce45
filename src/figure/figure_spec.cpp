#include "figure/figure_spec.h"

#include <cstdio>
#include <filesystem>
#include <functional>

#include "scene/scene.h"

namespace tissu {

namespace {

namespace fs = std::filesystem;

constexpr long long kMaxStep = 1'000'000'000;
constexpr int kMaxPanels = 64;

std::string format(const char* fmt, double value) {
  char buf[64];
  std::snprintf(buf, sizeof buf, fmt, value);
  return buf;
}

// Calls `out` with literal text pieces and `placeholder` with each {name}.
// Throws std::invalid_argument with a description of a malformed template.
void scan_template(const std::string& text, const std::function<void(const std::string&)>& literal,
                   const std::function<void(const std::string&)>& placeholder) {
  std::string piece;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if ((c == '{' || c == '}') && i + 1 < text.size() && text[i + 1] == c) {
      piece += c;
      ++i;
    } else if (c == '{') {
      const size_t close = text.find('}', i);
      if (close == std::string::npos) throw std::invalid_argument("unclosed \"{\"");
      literal(piece);
      piece.clear();
      placeholder(text.substr(i + 1, close - i - 1));
      i = close;
    } else if (c == '}') {
      throw std::invalid_argument("unmatched \"}\" (write }} for a brace)");
    } else {
      piece += c;
    }
  }
  literal(piece);
}

std::string placeholder_list() {
  std::string list;
  for (const auto& [name, meaning] : caption_placeholders()) {
    list += (list.empty() ? "{" : ", {") + name + "}";
  }
  return list;
}

PanelSpec parse_panel(const Json& value, const std::string& path, const fs::path& base) {
  JsonReader panel(value, path);
  PanelSpec p;
  p.path = path;
  const std::string scene = panel.string("scene");
  if (scene.empty()) throw InputError(panel.path_of("scene") + ": must not be empty");
  p.scene = (fs::path(scene).is_absolute() ? fs::path(scene) : base / scene).lexically_normal().string();
  std::error_code ec;
  if (!fs::is_regular_file(p.scene, ec)) {
    throw InputError(panel.path_of("scene") + ": no such scene file: " + p.scene);
  }
  if (panel.has("overrides")) {
    const Json& o = panel.raw("overrides");
    if (!o.is_object()) {
      throw InputError(panel.path_of("overrides") +
                       ": must be an object of dotted scene keys, e.g. {\"integrator\": "
                       "\"explicit_euler\"}");
    }
    for (auto it = o.begin(); it != o.end(); ++it) {
      const std::string& key = it.key();
      if (key.empty() || key.front() == '.' || key.back() == '.' ||
          key.find("..") != std::string::npos) {
        throw InputError(panel.path_of("overrides") + ": bad key \"" + key +
                         "\": expected a dotted scene path such as cloth.material");
      }
      p.overrides.emplace_back(key, it.value());
    }
  }
  p.step = panel.integer("step", Range::between(0, static_cast<double>(kMaxStep)));
  p.caption = panel.string("caption", "{name}");
  check_caption_template(p.caption, panel.path_of("caption"));
  panel.finish();
  return p;
}

}  // namespace

const std::vector<std::pair<std::string, std::string>>& caption_placeholders() {
  static const std::vector<std::pair<std::string, std::string>> list = {
      {"name", "scene name"},
      {"triangles", "triangle count"},
      {"vertices", "vertex count"},
      {"step", "iteration shown (the last good one when the run diverged)"},
      {"T", "wall time measured for simulating the panel, e.g. \"1.234 s\" (with "
            "--caption-times; else \"see report\")"},
      {"t", "simulated time of the state shown, e.g. \"0.260 s\""},
      {"integrator", "integrator name"},
      {"material", "material preset name (or \"custom\")"},
      {"dt", "time step, e.g. \"0.00013 s\""},
      {"correction", "\"with position correction\" or \"without position correction\""},
  };
  return list;
}

void check_caption_template(const std::string& text, const std::string& path) {
  try {
    scan_template(
        text, [](const std::string&) {},
        [&](const std::string& name) {
          for (const auto& known : caption_placeholders()) {
            if (known.first == name) return;
          }
          throw std::invalid_argument("unknown placeholder {" + name + "}; known: " +
                                      placeholder_list());
        });
  } catch (const std::invalid_argument& e) {
    throw InputError(path + ": " + e.what());
  }
}

std::string expand_caption(const std::string& text, const CaptionValues& v) {
  std::string out;
  scan_template(
      text, [&](const std::string& piece) { out += piece; },
      [&](const std::string& name) {
        if (name == "name") out += v.name;
        else if (name == "triangles") out += std::to_string(v.triangles);
        else if (name == "vertices") out += std::to_string(v.vertices);
        else if (name == "step") out += std::to_string(v.step);
        else if (name == "T") out += v.wall_seconds ? format("%.3f s", *v.wall_seconds) : "see report";
        else if (name == "t") out += format("%.3f s", v.time);
        else if (name == "integrator") out += v.integrator;
        else if (name == "material") out += v.material;
        else if (name == "dt") out += format("%.3g s", v.dt);
        else if (name == "correction")
          out += v.correction ? "with position correction" : "without position correction";
        else throw std::invalid_argument("unknown placeholder {" + name + "}");
      });
  return out;
}

FigureSpec parse_figure(const Json& doc, const std::string& file) {
  if (!doc.is_object()) {
    throw InputError(std::string("figure: must be an object, got ") + doc.type_name());
  }
  JsonReader root(doc, "");
  FigureSpec fig;
  fig.file = file;
  fig.title = root.string("title", "");
  if (root.has("panel_size")) {
    const std::vector<double> size = root.numbers("panel_size", 2, Range::between(16, 4096));
    for (int i = 0; i < 2; ++i) {
      if (size[i] != static_cast<int>(size[i]) || static_cast<int>(size[i]) % 2 != 0) {
        throw InputError(element_path("panel_size", i) + ": must be an even integer, got " +
                         format_number(size[i]));
      }
    }
    fig.panel_width = static_cast<int>(size[0]);
    fig.panel_height = static_cast<int>(size[1]);
  }
  fig.font_px = static_cast<int>(root.integer("font_size", 0, Range::between(6, 200)));
  const fs::path base = fs::path(file).parent_path();
  const Json& panels = root.raw("panels");
  if (!panels.is_array()) {
    throw InputError(std::string("panels: must be an array of panels, got ") + panels.type_name());
  }
  if (panels.empty()) throw InputError("panels: must list at least one panel");
  if (panels.size() > kMaxPanels) {
    throw InputError("panels: at most " + std::to_string(kMaxPanels) + " panels, got " +
                     std::to_string(panels.size()));
  }
  for (size_t i = 0; i < panels.size(); ++i) {
    fig.panels.push_back(parse_panel(panels[i], element_path("panels", i), base));
  }
  fig.columns = static_cast<int>(root.integer(
      "columns", static_cast<long long>(fig.panels.size()),
      Range::between(1, static_cast<double>(fig.panels.size()))));
  root.finish();
  return fig;
}

FigureSpec load_figure(const std::string& file) {
  std::error_code ec;
  if (!fs::is_regular_file(file, ec)) throw InputError(file + ": cannot open figure file");
  const Json doc = read_scene_json(file);  // JSON with comments; syntax errors name line:column
  try {
    return parse_figure(doc, file);
  } catch (const InputError& e) {
    throw InputError(file + ": " + e.what());
  }
}

}  // namespace tissu
