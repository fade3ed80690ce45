// tissu batch: a batch of scenes (a grid or a list of overrides of a base scene, or a list
// of scene files) run on this machine or handed to Slurm; its status; its gathering step.
#include <filesystem>
#include <iostream>

#include "app/batch_gather.h"
#include "app/batch_job.h"
#include "app/batch_local.h"
#include "app/batch_plan.h"
#include "app/batch_slurm.h"
#include "app/batch_spec.h"
#include "app/cli.h"
#include "app/commands.h"
#include "app/signals.h"
#include "core/error.h"
#include "physics/parallel.h"

namespace tissu {

namespace {

namespace fs = std::filesystem;

const char* kBatchHelp =
    "usage: tissu batch BATCH.json [--out DIR] [--executor local|slurm] [--jobs N] [--quiet]\n"
    "       tissu batch status DIR\n"
    "       tissu batch gather DIR\n"
    "       tissu batch job DIR --index I\n"
    "Runs every job of a batch file (docs/batch.md): a base scene with a grid or a list of\n"
    "overrides, or a list of scene files. Each job writes DIR/jobs/<name>/ (report.json,\n"
    "stills, video, log.txt, state.json); then DIR/summary.csv, DIR/summary.md and\n"
    "DIR/contact_sheet.png gather them. Running the batch again skips the jobs that are\n"
    "complete and reruns the others; DIR never holds two different batches.\n"
    "  --out DIR          batch directory (default out/<batch file stem>)\n"
    "  --executor E       local (default): a pool of tissu processes on this machine;\n"
    "                     slurm: a Slurm job array (sbatch --array) and a gathering job\n"
    "  --jobs N           local: jobs at once (default: processors / threads per job)\n"
    "  --quiet            no progress output\n"
    "  status DIR         each job's state, and the scheduler's for a slurm batch\n"
    "  gather DIR         write the summaries and the contact sheet again\n"
    "  job DIR --index I  run job I of DIR here (what each Slurm array task runs)\n"
    "Exit codes: 0 every job done (slurm: submitted; gather: summaries written), 1 some\n"
    "job failed or an output error, 2 bad batch file or usage (or DIR holds another\n"
    "batch, or this one is still on Slurm), 130 interrupted.\n";

struct BatchOptions {
  std::string batch_file;
  std::string out_dir;
  std::string executor = "local";
  int processes = 0;
  bool quiet = false;
};

int batch_exit_code(const GatherCounts& counts, bool interrupted) {
  if (interrupted) return kExitInterrupted;
  return counts.failed > 0 || counts.interrupted > 0 || counts.other > 0 ? kExitOutputError : kExitOk;
}

void print_counts(const BatchPlan& plan, const GatherCounts& counts) {
  std::cerr << "tissu: batch " << plan.name << ": " << counts.done << " done, " << counts.failed
            << " failed, " << counts.interrupted << " interrupted, " << counts.other
            << " not finished\n";
  for (const std::string& f : counts.failed_jobs) std::cerr << "tissu: batch: job " << f << "\n";
}

int run_batch(const BatchOptions& options) {
  const BatchSpec spec = read_batch_file(options.batch_file);
  const BatchPlan plan = plan_batch(spec, options.out_dir);
  claim_batch_dir(plan);
  const BatchDirLock lock(plan);
  refuse_while_queued(plan);
  std::vector<size_t> todo;
  for (size_t i = 0; i < plan.jobs.size(); ++i) {
    if (!job_complete(plan, i)) todo.push_back(i);
  }
  const size_t skipped = plan.jobs.size() - todo.size();

  if (options.executor == "slurm") {
    const SlurmSubmission s = submit_to_slurm(plan, todo);
    if (!options.quiet) {
      std::cerr << "tissu: batch " << plan.name << ": " << todo.size() << " jobs submitted ("
                << skipped << " complete, skipped): array job " << s.array_job
                << ", gathering job " << s.gather_job << "\n"
                << "tissu: batch: follow with `tissu batch status " << plan.dir << "`\n";
    }
    return kExitOk;
  }

  const int per_job = std::max(1, spec.threads);
  const int processes = options.processes > 0 ? options.processes
                                              : std::max(1, available_processors() / per_job);
  if (!options.quiet) {
    std::cerr << "tissu: batch " << plan.name << ": " << plan.jobs.size() << " jobs, " << skipped
              << " complete (skipped), " << todo.size() << " to run, " << processes
              << " at a time\n";
  }
  const bool interrupted = run_local_pool(plan, todo, {processes, !options.quiet});
  const GatherCounts counts = gather_batch(plan);
  if (!options.quiet) {
    print_counts(plan, counts);
    std::cerr << "tissu: batch: summary: " << (fs::path(plan.dir) / "summary.md").string() << "\n";
  }
  return batch_exit_code(counts, interrupted);
}

// "status DIR", "gather DIR", "job DIR --index I".
int batch_tool(const std::string& tool, const std::vector<std::string>& args) {
  const std::string command = "tissu batch " + tool;
  std::string dir;
  long long index = -1;
  if (!walk_arguments(args, command, kBatchHelp, [&](const std::string& a, const OptionValue& value) {
        if (tool == "job" && a == "--index") {
          index = parse_count("--index", value(), 0);
        } else if (!a.empty() && a[0] != '-' && dir.empty()) {
          dir = a;
        } else {
          return false;
        }
        return true;
      })) {
    return kExitOk;
  }
  if (dir.empty()) throw UsageError(command + ": missing DIR (see tissu batch --help)");
  const BatchPlan plan = read_batch_plan(dir);
  if (tool == "status") return print_batch_status(plan, std::cout);
  if (tool == "gather") {  // succeeds when it wrote the summaries, whatever the jobs did
    print_counts(plan, gather_batch(plan));
    return kExitOk;
  }
  if (index < 0) throw UsageError(command + ": missing --index I");
  if (static_cast<size_t>(index) >= plan.jobs.size()) {
    throw InputError("--index " + std::to_string(index) + ": the batch has " +
                     std::to_string(plan.jobs.size()) + " jobs (0 to " +
                     std::to_string(plan.jobs.size() - 1) + ")");
  }
  install_interrupt_handlers();  // a time limit's SIGTERM: record the job as interrupted
  const JobState state = run_job_here(plan, static_cast<size_t>(index), "slurm");
  std::cerr << "tissu: batch job " << plan.jobs[index].name << ": " << state.status
            << (state.error.empty() ? "" : ": " + state.error) << "\n";
  return state.status == "done" ? kExitOk : kExitOutputError;
}

}  // namespace

int command_batch(const std::vector<std::string>& args) {
  if (!args.empty() && (args[0] == "status" || args[0] == "gather" || args[0] == "job")) {
    return batch_tool(args[0], std::vector<std::string>(args.begin() + 1, args.end()));
  }
  BatchOptions options;
  if (!walk_arguments(args, "tissu batch", kBatchHelp, [&](const std::string& a, const OptionValue& value) {
        if (a == "--out") {
          options.out_dir = value();
        } else if (a == "--executor") {
          options.executor = value();
          if (options.executor != "local" && options.executor != "slurm") {
            throw UsageError("tissu batch: --executor: expected local or slurm, got \"" +
                             options.executor + "\"");
          }
        } else if (a == "--jobs") {
          options.processes = static_cast<int>(parse_count("--jobs", value(), 1, 1024));
        } else if (a == "--quiet") {
          options.quiet = true;
        } else if (!a.empty() && a[0] != '-' && options.batch_file.empty()) {
          options.batch_file = a;
        } else {
          return false;
        }
        return true;
      })) {
    return kExitOk;
  }
  if (options.batch_file.empty()) throw UsageError("tissu batch: missing BATCH.json (see --help)");
  if (options.out_dir.empty()) {
    options.out_dir = (fs::path("out") / fs::path(options.batch_file).stem()).string();
  }
  return run_batch(options);
}

}  // namespace tissu
