// What a caller keeps between steps: the thread count, the caches of the step (nothing is
// allocated after the first step) and what the last step measured.
#pragma once

#include <memory>

#include "physics/cloth_contact.h"

namespace tissu {

struct StepScratch;  // physics/step_scratch.h: force plan, buffers, implicit solver

// A Workspace serves one Model: its caches are planned from the model it first steps.
// Copies share the caches: do not step copies concurrently.
struct Workspace {
  // Threads a step may use (the calling thread included). Results do not depend on it.
  int threads = 1;
  // Implicit solver statistics of the last step (totals over its substeps).
  int newton_iterations = 0;
  int cg_iterations = 0;
  int factorizations = 0;  // of the Cholesky or scalar preconditioner
  int substeps = 0;
  int planned_substeps = 0;  // the substeps the last step was first tried with
  int barrier_pairs = 0;  // self and mesh feature pairs the barrier held at the end of its
                          // last solve (ImplicitReport::barrier_pairs)
  // The collision stage of the last step (cloth_contact.h) and its processor time, s.
  ContactStats contact;
  double contact_seconds = 0.0;
  std::shared_ptr<StepScratch> scratch;  // created by the first step
};

}  // namespace tissu
