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
// Counting video frames (count_frames), the count is ffmpeg's, with the simulated time:
//   render [#########-----------]  37%  frame=  45/120 time=1.500s  elapsed 0:12  ETA 0:20
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

  // From now on counts `total_frames` video frames, the last at simulated time `end_time`
  // (s): the line shows "frame=  45/120 time=1.500s", and the bar, percentage and ETA
  // follow the simulated time. Then update_frames() replaces update().
  void count_frames(long long total_frames, double end_time);
  // `frames` video frames are done and the simulation is at `time` (s).
  void update_frames(long long frames, double time);

  // Prints the final state ("done in 0:27", or "stopped after 0:12" short of the total).
  void finish();

  static std::string format_duration(double seconds);  // "0:07", "12:34", "1:02:03"

 private:
  std::string status_text(double elapsed) const;
  std::string count_text() const;
  double fraction() const;  // of the work, 0..1
  bool complete() const;
  void maybe_print();
  void print(double now);

  std::string label_;
  long long total_;
  std::ostream* out_;
  Settings settings_;
  double start_;
  double last_print_;
  long long done_ = 0;
  bool count_frames_ = false;
  long long total_frames_ = 0;
  double end_time_ = 0.0;  // s
  long long frames_ = 0;
  double time_ = 0.0;  // s
  bool printed_ = false;
  bool finished_ = false;
};

}  // namespace tissu
