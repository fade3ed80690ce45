// The gathering step of a batch: DIR/summary.csv and DIR/summary.md (one row per job: its
// overrides, status, times and the key results of its report) and DIR/contact_sheet.png
// (every job's stills with captions), from the jobs' own files only.
#pragma once

#include <string>
#include <vector>

#include "app/batch_plan.h"

namespace tissu {

struct GatherCounts {
  int done = 0, failed = 0, interrupted = 0, other = 0;  // other: pending, queued, running
  std::vector<std::string> failed_jobs;  // "name: error"
};

// Writes the summaries (and the contact sheet when the batch renders stills and some
// exist). Returns the counts of the jobs' states.
GatherCounts gather_batch(const BatchPlan& plan);

}  // namespace tissu
