// The slurm executor: a job array with one task per job (`tissu batch job DIR --index I`,
// resources per task from the batch file) and a gathering job after it
// (--dependency=afterany), both written to DIR/slurm/ and submitted with sbatch; and
// `tissu batch status`, which reads squeue and the jobs' own state files.
#pragma once

#include <iosfwd>
#include <string>
#include <vector>

#include "app/batch_plan.h"
#include "app/shell_words.h"  // shell_quote, for the scripts

namespace tissu {

struct SlurmSubmission {
  std::string array_job;   // "" when no job was left to run
  std::string gather_job;
};

// Writes DIR/slurm/array.sh and gather.sh, submits them, records the job ids in
// DIR/slurm/submitted.json and marks the jobs queued. OutputError (with sbatch's own
// message) when sbatch fails.
SlurmSubmission submit_to_slurm(const BatchPlan& plan, const std::vector<size_t>& todo);

// Refuses (InputError naming DIR and the Slurm job) to start the batch in DIR again while
// an earlier submission of it is still queued or running, so no job runs twice at once.
void refuse_while_queued(const BatchPlan& plan);

// One line per job (state, exit code, scheduler state, error), then the counts. Returns 0.
int print_batch_status(const BatchPlan& plan, std::ostream& out);

// "0-3,5,7-8" for sorted indices.
std::string index_ranges(const std::vector<size_t>& indices);

}  // namespace tissu
