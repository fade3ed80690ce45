// The four experiments of the paper's section 4; each appends its section of the document
// and its CSV rows to the report. `iterations` is 2000, or 200 in quick mode.
#pragma once

#include "study/paper/paper_experiments.h"
#include "study/paper/paper_report.h"

namespace tissu {

// (a) Wall time of the iterations on Tissu 1 and Tissu 2, rendering timed apart.
void paper_timing(const PaperOptions& options, PaperReport& report, long long iterations);

// (b) Where each integrator diverges without position correction, and how that moves.
void paper_divergence(const PaperOptions& options, PaperReport& report, long long iterations);

// (c) Distance from a converged reference, and free fall.
void paper_accuracy(const PaperOptions& options, PaperReport& report, long long iterations);

// (d) The cloth hung at 3 points (figure 11) after a long run.
void paper_hung(const PaperOptions& options, PaperReport& report);

}  // namespace tissu
