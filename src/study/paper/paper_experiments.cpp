#include "study/paper/paper_experiments.h"

#include <algorithm>
#include <filesystem>

#include "core/cpu_clock.h"
#include "core/error.h"
#include "study/paper/experiments.h"
#include "study/paper/paper_report.h"

namespace tissu {

namespace {

namespace fs = std::filesystem;

void check_options(const PaperOptions& o) {
  const std::vector<std::string> names = paper_experiment_names();
  for (const std::string& name : o.experiments) {
    if (std::find(names.begin(), names.end(), name) == names.end()) {
      throw InputError("paper experiments: unknown experiment \"" + name +
                       "\" (timing, divergence, accuracy, hung)");
    }
  }
  for (const char* f : {"tissu1.json", "tissu2.json", "piece990.json", "hung3.json"}) {
    const fs::path p = fs::path(o.scenes_dir) / f;
    std::error_code ec;
    if (!fs::is_regular_file(p, ec)) throw InputError(p.string() + ": scene file not found");
  }
}

}  // namespace

std::vector<std::string> paper_experiment_names() {
  return {"timing", "divergence", "accuracy", "hung"};
}

std::pair<std::string, std::string> run_paper_experiments(const PaperOptions& o) {
  check_options(o);
  const long long iterations = o.quick ? 200 : 2000;
  PaperReport r;
  r.log = o.log;
  const double start = wall_seconds();
  r.md += paper_report_header(o.command_line, o.quick);
  auto chosen = [&](const char* name) {
    return o.experiments.empty() ||
           std::find(o.experiments.begin(), o.experiments.end(), name) != o.experiments.end();
  };
  if (chosen("timing")) paper_timing(o, r, iterations);
  if (chosen("divergence")) paper_divergence(o, r, iterations);
  if (chosen("accuracy")) paper_accuracy(o, r, iterations);
  if (chosen("hung")) paper_hung(o, r);
  r.md += paper_report_footer(wall_seconds() - start);
  return write_paper_report(r, o.out_dir);
}

}  // namespace tissu
