#include "video/progress_bar.h"

#include <gtest/gtest.h>

#include <sstream>

namespace tissu {
namespace {

struct FakeClock {
  double now = 100.0;
  ProgressBar::Clock function() {
    return [this] { return now; };
  }
};

ProgressBar::Settings log_settings(FakeClock& clock, double interval) {
  ProgressBar::Settings settings;
  settings.is_terminal = false;
  settings.line_interval_s = interval;
  settings.clock = clock.function();
  return settings;
}

TEST(ProgressBar, LogWritesOneLinePerInterval) {
  FakeClock clock;
  std::ostringstream out;
  ProgressBar bar("simulate", 300, out, log_settings(clock, 5.0));
  clock.now += 1;
  bar.update(10);
  EXPECT_EQ(out.str(), "");  // interval not reached
  clock.now += 5;            // 6 s elapsed, 60 done: 10 steps per second, 240 to go
  bar.update(60);
  EXPECT_EQ(out.str(), "simulate: 60/300 (20%), elapsed 0:06, ETA 0:24\n");
  clock.now += 2;
  bar.update(80);
  EXPECT_EQ(out.str(), "simulate: 60/300 (20%), elapsed 0:06, ETA 0:24\n");
  clock.now += 3;
  bar.update(110);
  EXPECT_EQ(out.str(),
            "simulate: 60/300 (20%), elapsed 0:06, ETA 0:24\n"
            "simulate: 110/300 (36%), elapsed 0:11, ETA 0:19\n");
}

TEST(ProgressBar, FinishSaysDoneOrStopped) {
  FakeClock clock;
  std::ostringstream done_out, stopped_out;
  ProgressBar done("encode", 10, done_out, log_settings(clock, 5.0));
  ProgressBar stopped("encode", 10, stopped_out, log_settings(clock, 5.0));
  clock.now += 75;
  done.update(10);
  stopped.update(4);
  done.finish();
  stopped.finish();
  EXPECT_EQ(done_out.str(),
            "encode: 10/10 (100%), elapsed 1:15, ETA 0:00\nencode: 10/10 (100%), done in 1:15\n");
  EXPECT_EQ(stopped_out.str(),
            "encode: 4/10 (40%), elapsed 1:15, ETA 1:53\nencode: 4/10 (40%), stopped after 1:15\n");
}

TEST(ProgressBar, TerminalRedrawsOneLine) {
  FakeClock clock;
  std::ostringstream out;
  ProgressBar::Settings settings;
  settings.is_terminal = true;
  settings.redraw_interval_s = 0.1;
  settings.bar_width = 10;
  settings.clock = clock.function();
  ProgressBar bar("sim", 4, out, settings);
  bar.update(0);  // drawn at once
  EXPECT_EQ(out.str(), "\rsim [----------]   0%  0/4  elapsed 0:00  ETA --:--\x1b[K");
  out.str("");
  clock.now += 0.05;
  bar.update(1);
  EXPECT_EQ(out.str(), "");  // redraws are rate-limited
  clock.now += 1.95;         // 2 s for 2 steps
  bar.update(2);
  EXPECT_EQ(out.str(), "\rsim [#####-----]  50%  2/4  elapsed 0:02  ETA 0:02\x1b[K");
  out.str("");
  bar.finish();
  EXPECT_EQ(out.str(), "\rsim [#####-----]  50%  2/4  stopped after 0:02\x1b[K\n");
}

TEST(ProgressBar, UnknownTotalShowsCountOnly) {
  FakeClock clock;
  std::ostringstream out;
  ProgressBar bar("frames", 0, out, log_settings(clock, 1.0));
  clock.now += 2;
  bar.update(7);
  EXPECT_EQ(out.str(), "frames: 7, elapsed 0:02\n");
}

// Counting video frames, the line shows ffmpeg's "frame=" and the simulated time; the bar,
// percentage and ETA follow the simulated time up to the last frame's.
TEST(ProgressBar, CountsFramesAndSimulatedTime) {
  FakeClock clock;
  std::ostringstream out;
  ProgressBar::Settings settings;
  settings.is_terminal = true;
  settings.bar_width = 10;
  settings.clock = clock.function();
  ProgressBar bar("render", 75000, out, settings);
  bar.count_frames(121, 4.0);  // 30 fps over 4 s
  bar.update_frames(1, 0.0);
  EXPECT_EQ(out.str(), "\rrender [----------]   0%  frame=   1/121 time=0.000s  elapsed 0:00  ETA --:--\x1b[K");
  out.str("");
  clock.now += 10;
  bar.update_frames(31, 1.0);  // a quarter of the simulated time in 10 s
  EXPECT_EQ(out.str(), "\rrender [##--------]  25%  frame=  31/121 time=1.000s  elapsed 0:10  ETA 0:30\x1b[K");
  out.str("");
  clock.now += 30;
  bar.update_frames(121, 4.0);
  bar.finish();
  EXPECT_EQ(out.str(),
            "\rrender [##########] 100%  frame= 121/121 time=4.000s  elapsed 0:40  ETA 0:00\x1b[K"
            "\rrender [##########] 100%  frame= 121/121 time=4.000s  done in 0:40\x1b[K\n");

  std::ostringstream log;
  ProgressBar stopped("simulate", 300, log, log_settings(clock, 5.0));
  stopped.count_frames(16, 0.5);
  clock.now += 6;
  stopped.update_frames(8, 0.25);
  stopped.finish();
  EXPECT_EQ(log.str(),
            "simulate: frame=   8/16 time=0.250s (50%), elapsed 0:06, ETA 0:06\n"
            "simulate: frame=   8/16 time=0.250s (50%), stopped after 0:06\n");
}

TEST(ProgressBar, FormatsDurations) {
  EXPECT_EQ(ProgressBar::format_duration(0.4), "0:00");
  EXPECT_EQ(ProgressBar::format_duration(65), "1:05");
  EXPECT_EQ(ProgressBar::format_duration(3723), "1:02:03");
  EXPECT_EQ(ProgressBar::format_duration(-5), "0:00");
}

}  // namespace
}  // namespace tissu
