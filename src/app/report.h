// The run report (report.json): what ran, how it ended, time per stage, per-frame rows.
#pragma once

#include "core/partial_file.h"  // write_text_file, for the report

#include <string>

#include "app/run_loop.h"
#include "scene/json_reader.h"

namespace tissu {

// {"version": project() VERSION, "git_commit": the commit built, or "unknown" outside git,
//  "git_modified": whether the tracked files differed from it when it was built}.
nlohmann::ordered_json tissu_identity();

nlohmann::ordered_json make_report(const Scene& scene, const Model& model, const RunResult& result);


}  // namespace tissu
