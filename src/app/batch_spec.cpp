#include "app/batch_spec.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "core/error.h"
#include "study/paper/paper_experiments.h"
#include "scene/json_reader.h"
#include "scene/scene.h"

namespace tissu {

namespace {

namespace fs = std::filesystem;
using Ordered = nlohmann::ordered_json;

// A value as `--set` reads it back: strings bare unless they would parse as JSON.
std::string override_text(const nlohmann::json& value) {
  if (!value.is_string()) return value.dump();
  const std::string text = value.get<std::string>();
  // "1e-4" as a string stays a string.
  return nlohmann::json::accept(text) ? value.dump() : text;
}

std::string name_part(const std::string& text) {
  std::string out;
  for (char c : text) {
    const bool keep = std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '_' || c == '+' || c == '-';
    out += keep ? c : '-';
  }
  return out;
}

std::string last_segment(const std::string& key) {
  const size_t dot = key.rfind('.');
  return dot == std::string::npos ? key : key.substr(dot + 1);
}

// The overrides of an object {"key": value, ...} at `path`.
std::vector<JobOverride> overrides_of(const Ordered& object, const std::string& path) {
  if (!object.is_object()) throw InputError(path + ": expected an object of KEY: VALUE overrides");
  std::vector<JobOverride> out;
  for (auto it = object.begin(); it != object.end(); ++it) {
    if (it.key().empty()) throw InputError(path + ": empty override key");
    out.push_back({it.key(), nlohmann::json::parse(it.value().dump())});
  }
  return out;
}

// Every combination of the grid's values, the first key varying slowest.
std::vector<std::vector<JobOverride>> expand_grid(const Ordered& grid, const std::string& path) {
  if (!grid.is_object() || grid.empty()) {
    throw InputError(path + ": expected an object of KEY: [VALUES] with at least one key");
  }
  std::vector<std::vector<JobOverride>> combos{{}};
  for (auto it = grid.begin(); it != grid.end(); ++it) {
    const std::string at = path + "." + it.key();
    if (!it.value().is_array() || it.value().empty()) {
      throw InputError(at + ": expected a non-empty list of values");
    }
    std::vector<std::vector<JobOverride>> next;
    for (const auto& combo : combos) {
      for (const Ordered& v : it.value()) {
        next.push_back(combo);
        next.back().push_back({it.key(), nlohmann::json::parse(v.dump())});
      }
    }
    combos = std::move(next);
  }
  return combos;
}

std::string absolute_next_to(const std::string& name, const std::string& batch_file) {
  fs::path p(name);
  if (p.is_relative()) p = fs::path(batch_file).parent_path() / p;
  return fs::absolute(p).lexically_normal().string();
}

// Makes the names unique in order: the second "x" becomes "x-2".
void make_names_unique(std::vector<BatchJob>& jobs) {
  std::map<std::string, int> seen;
  for (const BatchJob& j : jobs) seen[j.name] = 0;
  std::map<std::string, int> count;
  for (BatchJob& j : jobs) {
    const int n = ++count[j.name];
    if (n == 1) continue;
    std::string candidate;
    for (int k = n;; ++k) {
      candidate = j.name + "-" + std::to_string(k);
      if (!seen.count(candidate)) break;
    }
    seen[candidate] = 0;
    j.name = candidate;
  }
}

void read_slurm(JsonReader& top, SlurmResources& out) {
  if (!top.has("slurm")) {
    top.accept("slurm");
    return;
  }
  JsonReader r = top.object("slurm");
  out.cpus_per_task = static_cast<int>(r.integer("cpus_per_task", 1, Range::between(1, 4096)));
  out.mem = r.string("mem", "");
  out.time = r.string("time", "");
  out.partition = r.string("partition", "");
  out.account = r.string("account", "");
  if (r.has("sbatch")) {
    const Json& extra = r.raw("sbatch");
    if (!extra.is_array()) throw InputError(r.path_of("sbatch") + ": expected a list of sbatch options");
    for (const Json& e : extra) {
      if (!e.is_string()) throw InputError(r.path_of("sbatch") + ": expected strings");
      out.extra.push_back(e.get<std::string>());
    }
  } else {
    r.accept("sbatch");
  }
  r.finish();
}

// Further options of each job's command, as given; not those the batch sets itself.
std::vector<std::string> checked_options(const Json& list, const std::string& path) {
  if (!list.is_array()) throw InputError(path + ": expected a list of command-line options");
  std::vector<std::string> out;
  for (size_t i = 0; i < list.size(); ++i) {
    if (!list[i].is_string()) throw InputError(element_path(path, i) + ": expected a string");
    const std::string o = list[i].get<std::string>();
    for (const char* own : {"--out", "--out-dir", "--report", "-y", "--overwrite", "--quiet", "--threads",
                            "--stills", "--frames", "--no-mp4", "--set"}) {
      if (o == own) {
        throw InputError(element_path(path, i) + ": " + o + " is set by the batch itself (see docs/batch.md)");
      }
    }
    out.push_back(o);
  }
  return out;
}

BatchSpec parse_batch(const Json& doc, const Ordered& ordered, const std::string& file) {
  BatchSpec b;
  b.file = file;
  if (!doc.is_object()) throw InputError("expected a JSON object (see docs/batch.md)");
  JsonReader r(doc, "");
  b.name = r.string("name", fs::path(file).stem().string());
  const bool has_figures = doc.contains("figures");
  const bool has_experiments = doc.contains("experiments");
  b.produce = r.choice("produce", {"run", "render", "stills", "figure", "study", "paper"},
                       has_figures ? "figure" : has_experiments ? "paper" : "render");
  if ((b.produce == "paper") != has_experiments) {
    throw InputError(has_experiments ? r.path_of("produce") + ": a list of \"experiments\" produces \"paper\""
                                     : r.path_of("produce") + ": \"paper\" needs \"experiments\", a list of the paper's experiments");
  }
  if (has_experiments) {
    for (const char* key : {"scene", "scenes", "set", "grid", "list", "stills", "frames", "threads", "figures"}) {
      if (doc.contains(key)) {
        throw InputError(std::string(key) + ": a list of \"experiments\" takes no \"" + key +
                         "\" (the paper's experiments use the scenes of \"paper_scenes\")");
      }
    }
  }
  if ((b.produce == "figure") != has_figures) {
    throw InputError(has_figures ? r.path_of("produce") + ": a list of \"figures\" produces \"figure\""
                                 : r.path_of("produce") + ": \"figure\" needs \"figures\", a list of figure files");
  }
  if (has_figures && b.produce == "figure") {
    for (const char* key : {"scene", "scenes", "set", "grid", "list", "stills", "frames", "threads"}) {
      if (doc.contains(key)) {
        throw InputError(std::string(key) + ": a list of \"figures\" takes no \"" + key +
                         "\" (a figure file names its own scenes)");
      }
    }
  }
  b.stills = static_cast<int>(r.integer("stills", b.produce == "stills" ? 4 : 0, Range::between(0, 1000)));
  if (b.produce == "stills" && b.stills == 0) {
    throw InputError(r.path_of("stills") + ": produce \"stills\" needs at least one still");
  }
  if (b.produce == "run" && b.stills > 0) {
    throw InputError(r.path_of("stills") + ": produce \"run\" renders no stills (use \"render\" or \"stills\")");
  }
  if (b.produce == "study" && b.stills > 0) {
    throw InputError(r.path_of("stills") + ": produce \"study\" renders no stills (its plot is study.png)");
  }
  b.frames = r.integer("frames", 0, Range::between(0, 1e12));
  b.threads = static_cast<int>(r.integer("threads", 1, Range::between(1, 256)));
  read_slurm(r, b.slurm);
  if (r.has("options")) b.options = checked_options(r.raw("options"), r.path_of("options"));
  r.accept("options");
  if (doc.contains("paper_scenes") && !has_experiments) {
    throw InputError(r.path_of("paper_scenes") + ": only with \"experiments\"");
  }
  const std::string paper_scenes = r.string("paper_scenes", "../paper");  // next to scenes/batches/
  for (const char* key : {"scene", "scenes", "set", "grid", "list", "figures", "experiments"}) r.accept(key);
  r.finish();

  if (has_experiments) {
    // One `tissu paper --experiments NAME` job each; the scenes directory is the job's
    // scene_file, its results DIR/jobs/<name>/paper-results.md and .csv.
    const Ordered& list = ordered["experiments"];
    if (!list.is_array() || list.empty()) {
      throw InputError("experiments: expected a non-empty list (timing, divergence, accuracy, hung)");
    }
    const std::vector<std::string> names = paper_experiment_names();
    const std::string scenes = absolute_next_to(paper_scenes, file);
    for (size_t i = 0; i < list.size(); ++i) {
      const std::string name = list[i].is_string() ? list[i].get<std::string>() : "";
      if (std::find(names.begin(), names.end(), name) == names.end()) {
        throw InputError(element_path("experiments", i) +
                         ": expected one of timing, divergence, accuracy, hung");
      }
      b.jobs.push_back({name, scenes, {}});
    }
    make_names_unique(b.jobs);
    b.hash = fnv1a_hex(doc.dump());
    return b;
  }

  if (has_figures) {
    const Ordered& figures = ordered["figures"];
    if (!figures.is_array() || figures.empty()) throw InputError("figures: expected a non-empty list of figure files");
    for (size_t i = 0; i < figures.size(); ++i) {
      if (!figures[i].is_string()) throw InputError(element_path("figures", i) + ": expected a figure file name");
      const std::string figure = absolute_next_to(figures[i].get<std::string>(), file);
      b.jobs.push_back({name_part(fs::path(figure).stem().string()), figure, {}});
    }
    make_names_unique(b.jobs);
    b.hash = fnv1a_hex(doc.dump());
    return b;
  }

  const bool has_scene = doc.contains("scene"), has_scenes = doc.contains("scenes");
  if (has_scene == has_scenes) {
    throw InputError(has_scene ? "scenes: give either \"scene\" (with a grid or a list) or \"scenes\", not both"
                               : "scene: missing (a base scene, or \"scenes\": a list of scene files)");
  }
  if (doc.contains("grid") && doc.contains("list")) {
    throw InputError("list: give either \"grid\" or \"list\", not both");
  }
  if (has_scenes && (doc.contains("grid") || doc.contains("list"))) {
    throw InputError(std::string(doc.contains("grid") ? "grid" : "list") +
                     ": a list of \"scenes\" takes no grid or list (use \"set\" for every scene)");
  }
  const std::vector<JobOverride> common =
      doc.contains("set") ? overrides_of(ordered["set"], "set") : std::vector<JobOverride>{};

  if (has_scenes) {
    const Ordered& scenes = ordered["scenes"];
    if (!scenes.is_array() || scenes.empty()) throw InputError("scenes: expected a non-empty list of scene files");
    for (size_t i = 0; i < scenes.size(); ++i) {
      if (!scenes[i].is_string()) throw InputError(element_path("scenes", i) + ": expected a scene file name");
      const std::string scene = absolute_next_to(scenes[i].get<std::string>(), file);
      b.jobs.push_back({name_part(fs::path(scene).stem().string()), scene, common});
    }
  } else {
    if (!doc["scene"].is_string()) throw InputError("scene: expected a scene file name");
    const std::string scene = absolute_next_to(doc["scene"].get<std::string>(), file);
    std::vector<std::vector<JobOverride>> sets;
    if (doc.contains("grid")) {
      sets = expand_grid(ordered["grid"], "grid");
    } else if (doc.contains("list")) {
      const Ordered& list = ordered["list"];
      if (!list.is_array() || list.empty()) throw InputError("list: expected a non-empty list of override objects");
      for (size_t i = 0; i < list.size(); ++i) sets.push_back(overrides_of(list[i], element_path("list", i)));
    } else {
      sets.push_back({});
    }
    for (const auto& own : sets) {
      BatchJob job;
      job.scene_file = scene;
      job.name = own.empty() ? name_part(fs::path(scene).stem().string()) : job_name_of(own);
      job.overrides = common;
      job.overrides.insert(job.overrides.end(), own.begin(), own.end());
      b.jobs.push_back(std::move(job));
    }
  }
  make_names_unique(b.jobs);
  b.hash = fnv1a_hex(doc.dump());
  return b;
}

}  // namespace

std::string JobOverride::assignment() const { return key + "=" + override_text(value); }

std::string job_name_of(const std::vector<JobOverride>& overrides) {
  // The last segment of each key, unless two keys share it: then the whole keys.
  std::set<std::string> lasts;
  bool clash = false;
  for (const JobOverride& o : overrides) clash |= !lasts.insert(last_segment(o.key)).second;
  std::string name;
  for (const JobOverride& o : overrides) {
    if (!name.empty()) name += "_";
    const std::string value = o.value.is_string() ? o.value.get<std::string>() : o.value.dump();
    name += name_part(clash ? o.key : last_segment(o.key)) + "-" + name_part(value);
  }
  return name.empty() ? "base" : name;
}

std::string fnv1a_hex(const std::string& text) {
  std::uint64_t h = 1469598103934665603ull;
  for (unsigned char c : text) {
    h ^= c;
    h *= 1099511628211ull;
  }
  char out[17];
  std::snprintf(out, sizeof out, "%016llx", static_cast<unsigned long long>(h));
  return out;
}

BatchSpec read_batch_file(const std::string& file) {
  std::error_code ec;
  if (!fs::is_regular_file(file, ec)) {
    throw InputError(file + ": cannot open batch file" +
                     (fs::exists(file, ec) ? ": not a regular file" : ": no such file"));
  }
  const Json doc = read_scene_json(file);  // syntax errors with line and column
  std::ifstream in(file, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  // The same document with its keys in file order (grid axes vary in the order written).
  const Ordered ordered = Ordered::parse(text.str(), nullptr, true, /*ignore_comments=*/true);
  try {
    return parse_batch(doc, ordered, file);
  } catch (const InputError& e) {
    throw InputError(file + ": " + e.what());
  }
}

std::vector<std::string> job_arguments(const BatchSpec& batch, const BatchJob& job,
                                       const std::string& job_dir) {
  std::vector<std::string> args;
  if (batch.produce == "figure") {
    // The figure file is the job's scene_file; its image is DIR/jobs/<name>/figure.png.
    args = {"figure", job.scene_file, "--out", job_dir + "/figure.png", "--quiet"};
  } else if (batch.produce == "study") {
    args = {"study", job.scene_file, "--out", job_dir, "--quiet"};
  } else if (batch.produce == "paper") {
    args = {"paper", "--experiments", job.name, "--scenes", job.scene_file, "--out", job_dir, "--quiet"};
  } else {
    args = {batch.produce == "run" ? "run" : "render", job.scene_file, "--out", job_dir,
            "--overwrite", "--quiet", "--threads", std::to_string(batch.threads)};
  }
  for (const JobOverride& o : job.overrides) {
    args.push_back("--set");
    args.push_back(o.assignment());
  }
  args.insert(args.end(), batch.options.begin(), batch.options.end());
  if (batch.produce == "render" || batch.produce == "stills") {
    if (batch.produce == "stills") args.push_back("--no-mp4");
    if (batch.stills > 0) {
      args.push_back("--stills");
      args.push_back(std::to_string(batch.stills));
    }
    if (batch.frames > 0) {
      args.push_back("--frames");
      args.push_back(std::to_string(batch.frames));
    }
  }
  return args;
}

}  // namespace tissu
