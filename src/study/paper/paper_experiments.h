// The experiments of the paper's section 4, measured on this machine, written as
// docs/paper-results.md and docs/paper-results.csv by `tissu paper`:
//  (a) wall time of 2000 iterations on "Tissu 1" (4847 triangles) and "Tissu 2" (961) for
//      the paper's three integrators, next to the paper's times; rendering timed apart;
//  (b) the iteration at which each integrator diverges without position correction on the
//      990-triangle piece, whether 2000 iterations run with it, and how the divergence
//      point moves with the time step, the stiffness and the correction's settings;
//  (c) the distance of each integrator's result from a converged small-step reference, and
//      what the paper's halving of every acceleration (h F / (2 m)) does to the motion;
//  (d) the cloth hung at 3 points (figure 11) after a long run.
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace tissu {

struct PaperOptions {
  std::string scenes_dir = "scenes/paper";  // tissu1.json, tissu2.json, piece990.json, hung3.json
  std::string out_dir = "out/paper";        // paper-results.md and paper-results.csv
  std::string command_line;                 // shown in the generated document
  bool quick = false;   // fewer iterations and table cells: checks the command, not the results
  int repeats = 5;      // timed runs per case (the fastest and the median are reported)
  // Which experiments (paper_experiment_names()); empty = all of them.
  std::vector<std::string> experiments;
  std::function<void(const std::string&)> log;  // progress lines; may be empty
};

// "timing", "divergence", "accuracy", "hung": the experiments, in the order they run.
std::vector<std::string> paper_experiment_names();

// Runs the chosen experiments and writes the two files (atomically). Returns their paths.
// Throws InputError for bad scenes, OutputError when the files cannot be written.
std::pair<std::string, std::string> run_paper_experiments(const PaperOptions& options);

}  // namespace tissu
