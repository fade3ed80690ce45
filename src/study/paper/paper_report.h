// The document the paper's experiments write: Markdown text (docs/paper-results.md) and CSV
// rows (docs/paper-results.csv), with the header that says how and where they were measured.
#pragma once

#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace tissu {

// One measured quantity: experiment, scene, integrator, dt (s, omitted when 0), stiffness
// scale (omitted when 0), position correction, quantity, value, unit, the paper's value.
struct PaperCsvRow {
  std::string experiment, scene, integrator;
  double dt = 0, stiffness_scale = 1;
  std::string correction, quantity, value, unit, paper;
};

struct PaperReport {
  std::string md;
  std::vector<PaperCsvRow> csv;
  std::function<void(const std::string&)> log;  // progress lines; may be empty
  void say(const std::string& line) const {
    if (log) log(line);
  }
};

// The title, how the document was made (command line, date, quick mode) and the machine.
std::string paper_report_header(const std::string& command_line, bool quick);

// The closing line: load average and the wall time of all experiments (s).
std::string paper_report_footer(double seconds);

// The CSV text: a header line, then one line per row.
std::string paper_report_csv(const std::vector<PaperCsvRow>& rows);

// Writes DIR/paper-results.md and DIR/paper-results.csv, each atomically; returns the paths.
std::pair<std::string, std::string> write_paper_report(const PaperReport& report,
                                                       const std::string& dir);

}  // namespace tissu
