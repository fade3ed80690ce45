// The local executor: a pool of child tissu processes on this machine, one progress line
// for the whole batch.
#pragma once

#include <cstddef>
#include <vector>

#include "app/batch_plan.h"

namespace tissu {

struct LocalPoolOptions {
  int processes = 1;  // jobs running at once
  bool progress = true;
};

// Runs the jobs `todo` (indices into plan.jobs). A first SIGINT or SIGTERM starts no
// more jobs and passes the signal on to the running ones, which stop after their current
// frame. Returns true when it was interrupted.
bool run_local_pool(const BatchPlan& plan, const std::vector<size_t>& todo,
                    const LocalPoolOptions& options);

}  // namespace tissu
