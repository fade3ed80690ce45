#include "app/batch_gather.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "app/report.h"
#include "figure/compose.h"
#include "scene/json_reader.h"
#include "study/output.h"
#include "video/png_io.h"

namespace tissu {

namespace {

namespace fs = std::filesystem;

std::string key_of(const std::string& assignment) { return assignment.substr(0, assignment.find('=')); }
std::string value_of(const std::string& assignment) {
  const size_t eq = assignment.find('=');
  return eq == std::string::npos ? "" : assignment.substr(eq + 1);
}

std::string number_text(const nlohmann::json& value) {
  if (value.is_number_integer()) return std::to_string(value.get<long long>());
  if (value.is_number()) return format_number(value.get<double>());
  return "";
}

// The value at a path of keys in the report, as text ("" when absent).
std::string report_value(const nlohmann::json& report, std::initializer_list<const char*> path) {
  const nlohmann::json* node = &report;
  for (const char* key : path) {
    if (!node->is_object() || !node->contains(key)) return "";
    node = &(*node)[key];
  }
  return node->is_string() ? node->get<std::string>() : number_text(*node);
}

struct Row {
  std::vector<std::string> cells;
};

// The columns: the job, each override key of the batch (in the order first met), then
// the job's state and the key results of its report.
std::vector<std::string> override_keys(const BatchPlan& plan) {
  std::vector<std::string> keys;
  for (const PlannedJob& j : plan.jobs) {
    for (const std::string& o : j.overrides) {
      if (std::find(keys.begin(), keys.end(), key_of(o)) == keys.end()) keys.push_back(key_of(o));
    }
  }
  return keys;
}

const char* kResultColumns[] = {"status", "exit_code", "started", "finished", "wall_s",
                                "steps_done", "simulated_time", "ms_per_step", "triangles",
                                "end_kinetic_energy", "end_max_strain", "error"};

std::vector<std::string> row_of(const BatchPlan& plan, size_t i, const std::vector<std::string>& keys,
                                const JobState& s) {
  std::vector<std::string> row{plan.jobs[i].name};
  for (const std::string& k : keys) {
    std::string v;
    for (const std::string& o : plan.jobs[i].overrides) {
      if (key_of(o) == k) v = value_of(o);
    }
    row.push_back(v);
  }
  const nlohmann::json report =
      read_json_file(fs::path(plan.job_dir(i)) / "report.json").value_or(nlohmann::json(nullptr));
  const bool ran = s.status == "done" || s.status == "failed" || s.status == "interrupted";
  row.push_back(s.status);
  row.push_back(ran ? std::to_string(s.exit_code) : "");
  row.push_back(s.started);
  row.push_back(s.finished);
  row.push_back(ran ? format_number(std::round(s.wall_s * 1000) / 1000) : "");
  // A report left by an earlier run of a job now pending or running is not its result.
  const nlohmann::json none;
  const nlohmann::json& r = ran ? report : none;
  row.push_back(report_value(r, {"steps_done"}));
  row.push_back(report_value(r, {"simulated_time"}));
  row.push_back(report_value(r, {"ms_per_step"}));
  row.push_back(report_value(r, {"triangles"}));
  // The state at the end: the report's "end" row, else its last frame.
  nlohmann::json end = r.is_object() && r.contains("end") ? r["end"] : nlohmann::json();
  if (end.is_null() && r.is_object() && r.contains("frames") && r["frames"].is_array() && !r["frames"].empty()) {
    end = r["frames"].back();
  }
  row.push_back(report_value(end, {"kinetic_energy"}));
  row.push_back(report_value(end, {"max_strain"}));
  row.push_back(s.error);
  return row;
}

std::string md_cell(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (c == '|') out += "\\|";
    else if (c == '\n') out += ' ';
    else out += c;
  }
  return out;
}

// The one picture of a figure or study job; "" for jobs with stills.
const char* single_picture(const BatchPlan& plan) {
  return plan.produce == "figure" ? "figure.png" : plan.produce == "study" ? "study.png" : "";
}

// A job's pictures for the contact sheet: its stills, or its figure or study plot.
std::vector<fs::path> stills_of(const fs::path& job_dir, const std::string& single) {
  std::vector<fs::path> out;
  std::error_code ec;
  if (!single.empty()) {
    if (fs::is_regular_file(job_dir / single, ec)) out.push_back(job_dir / single);
    return out;
  }
  for (const auto& e : fs::directory_iterator(job_dir / "stills", ec)) {
    if (e.path().extension() == ".png") out.push_back(e.path());
  }
  std::sort(out.begin(), out.end());
  return out;
}

// Nearest-neighbour scaling, for stills of a size other than the first one's.
Image scaled(const Image& in, int w, int h) {
  if (in.width == w && in.height == h) return in;
  Image out(w, h);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const uint8_t* p = in.pixel(x * in.width / w, y * in.height / h);
      std::copy(p, p + 3, out.pixel(x, y));
    }
  }
  return out;
}

Image grey_panel(int w, int h) {
  Image out(w, h);
  std::fill(out.rgb.begin(), out.rgb.end(), uint8_t{200});
  return out;
}

// A job's caption: its overrides that vary across the batch, "material=silk dt=0.002"
// (spaces let long captions wrap), else its name.
std::string caption_of(const BatchPlan& plan, size_t i) {
  std::string caption;
  for (const std::string& o : plan.jobs[i].overrides) {
    const bool shared = std::all_of(plan.jobs.begin(), plan.jobs.end(), [&](const PlannedJob& j) {
      return std::find(j.overrides.begin(), j.overrides.end(), o) != j.overrides.end();
    });
    if (shared) continue;
    const std::string key = key_of(o);
    const size_t dot = key.rfind('.');
    caption += (caption.empty() ? "" : " ") + key.substr(dot == std::string::npos ? 0 : dot + 1) +
               "=" + value_of(o);
  }
  return caption.empty() || plan.jobs.size() == 1 ? plan.jobs[i].name : caption;
}

// One row of panels per job (its stills in order); a job without its stills shows grey
// panels captioned with its status. Nothing is written when no job has a still.
void write_contact_sheet(const BatchPlan& plan, const std::vector<JobState>& states) {
  std::vector<std::vector<fs::path>> stills;
  int w = 0, h = 0;
  for (size_t i = 0; i < plan.jobs.size(); ++i) {
    stills.push_back(stills_of(plan.job_dir(i), single_picture(plan)));
    if (w == 0 && !stills.back().empty()) {
      const Image first = read_png(stills.back().front().string());
      w = first.width;
      h = first.height;
    }
  }
  if (w == 0) return;
  const int per_job = *single_picture(plan) ? 1 : plan.stills;
  std::vector<Image> panels;
  std::vector<std::string> captions;
  for (size_t i = 0; i < plan.jobs.size(); ++i) {
    const bool usable = states[i].status == "done" && static_cast<int>(stills[i].size()) >= per_job;
    for (int k = 0; k < per_job; ++k) {
      std::string caption = caption_of(plan, i);
      if (per_job > 1) caption += " (" + std::to_string(k + 1) + "/" + std::to_string(per_job) + ")";
      if (usable) {
        panels.push_back(scaled(read_png(stills[i][k].string()), w, h));
      } else {
        panels.push_back(grey_panel(w, h));
        caption += ": " + states[i].status;
      }
      captions.push_back(caption);
    }
  }
  FigureLayout layout;
  layout.columns = per_job > 1 ? per_job : std::min<int>(4, static_cast<int>(panels.size()));
  layout.title = plan.name + ": " + std::to_string(plan.jobs.size()) + " jobs";
  write_png((fs::path(plan.dir) / "contact_sheet.png").string(), compose_figure(panels, captions, layout));
}

}  // namespace

GatherCounts gather_batch(const BatchPlan& plan) {
  const std::vector<std::string> keys = override_keys(plan);
  std::vector<std::string> header{"job"};
  header.insert(header.end(), keys.begin(), keys.end());
  header.insert(header.end(), std::begin(kResultColumns), std::end(kResultColumns));

  GatherCounts counts;
  std::vector<JobState> states;
  std::vector<std::vector<std::string>> rows;
  for (size_t i = 0; i < plan.jobs.size(); ++i) {
    states.push_back(read_job_state(plan, i));
    const JobState& s = states.back();
    if (s.status == "done") ++counts.done;
    else if (s.status == "failed") ++counts.failed;
    else if (s.status == "interrupted") ++counts.interrupted;
    else ++counts.other;
    if (s.status == "failed") counts.failed_jobs.push_back(plan.jobs[i].name + ": " + s.error);
    rows.push_back(row_of(plan, i, keys, s));
  }

  std::ostringstream csv;
  for (size_t c = 0; c < header.size(); ++c) csv << (c ? "," : "") << csv_field(header[c]);
  csv << "\n";
  for (const auto& row : rows) {
    for (size_t c = 0; c < row.size(); ++c) csv << (c ? "," : "") << csv_field(row[c]);
    csv << "\n";
  }
  write_text_file((fs::path(plan.dir) / "summary.csv").string(), csv.str());

  std::ostringstream md;
  md << "# Batch " << plan.name << "\n\n"
     << "Batch file: `" << plan.batch_file << "`; " << plan.jobs.size() << " jobs: " << counts.done
     << " done, " << counts.failed << " failed, " << counts.interrupted << " interrupted, "
     << counts.other << " not finished.\n\n";
  for (size_t c = 0; c < header.size(); ++c) md << "| " << md_cell(header[c]) << " ";
  md << "|\n";
  for (size_t c = 0; c < header.size(); ++c) md << "|---";
  md << "|\n";
  for (const auto& row : rows) {
    for (const std::string& cell : row) md << "| " << md_cell(cell) << " ";
    md << "|\n";
  }
  const bool pictures = plan.stills > 0 || *single_picture(plan);
  if (pictures) md << "\nContact sheet: contact_sheet.png\n";
  write_text_file((fs::path(plan.dir) / "summary.md").string(), md.str());

  if (pictures) write_contact_sheet(plan, states);
  return counts;
}

}  // namespace tissu
