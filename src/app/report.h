// The run report (report.json): what ran, how it ended, time per stage, per-frame rows.
#pragma once

#include <string>

#include "app/run_loop.h"
#include "scene/json_reader.h"

namespace tissu {

// {"version": project() VERSION, "git_commit": the commit configured from, or "unknown"}.
nlohmann::ordered_json tissu_identity();

nlohmann::ordered_json make_report(const Scene& scene, const Model& model, const RunResult& result);

// Writes `text` to `path` atomically (temporary file, then rename).
void write_text_file(const std::string& path, const std::string& text);

}  // namespace tissu
