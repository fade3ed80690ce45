// Progress with elapsed time and ETA for long runs, normally on stderr.
#pragma once

#include <functional>
#include <iosfwd>
#include <string>

namespace tissu {

// On a terminal the bar is redrawn in place (at most `redraw_interval_s` apart):
//   simulate [#########-----------]  45%  135/300  elapsed 0:12  ETA 0:15
// Otherwise (a log file, CI) one line is written every `line_interval_s`:
//   simulate: 135/300 (45%), elapsed 0:12, ETA 0:15
// The clock returns seconds from any fixed origin; tests pass a fake one.
class ProgressBar {
 public:
  using Clock = std::function<double()>;

  struct Settings {
    bool is_terminal = false;
    double line_interval_s = 5.0;
    double redraw_interval_s = 0.1;
    int bar_width = 24;
    Clock clock;  // empty: std::chrono::steady_clock
  };

  ProgressBar(std::string label, long long total, std::ostream& out, Settings settings);

  // Writes to std::cerr, redrawing when stderr is a terminal.
  static ProgressBar on_stderr(std::string label, long long total);

  // `done` of `total` steps are complete; prints when the interval has passed.
  void update(long long done);

  // Prints the final state ("done in 0:27", or "stopped at 135/300 after 0:12").
  void finish();

  static std::string format_duration(double seconds);  // "0:07", "12:34", "1:02:03"

 private:
  std::string status_text(long long done, double elapsed) const;
  void print(long long done, double now);

  std::string label_;
  long long total_;
  std::ostream* out_;
  Settings settings_;
  double start_;
  double last_print_;
  long long done_ = 0;
  bool printed_ = false;
  bool finished_ = false;
};

}  // namespace tissu
