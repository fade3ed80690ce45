#include "video/progress_bar.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>

namespace tissu {

static double steady_seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

ProgressBar::ProgressBar(std::string label, long long total, std::ostream& out, Settings settings)
    : label_(std::move(label)), total_(total), out_(&out), settings_(std::move(settings)) {
  if (!settings_.clock) settings_.clock = steady_seconds;
  start_ = settings_.clock();
  last_print_ = start_;
}

ProgressBar ProgressBar::on_stderr(std::string label, long long total) {
  Settings settings;
  settings.is_terminal = ::isatty(STDERR_FILENO) == 1;
  return ProgressBar(std::move(label), total, std::cerr, settings);
}

std::string ProgressBar::format_duration(double seconds) {
  const long long s = std::llround(std::max(0.0, seconds));
  char text[32];
  if (s >= 3600) {
    std::snprintf(text, sizeof text, "%lld:%02lld:%02lld", s / 3600, s / 60 % 60, s % 60);
  } else {
    std::snprintf(text, sizeof text, "%lld:%02lld", s / 60, s % 60);
  }
  return text;
}

std::string ProgressBar::status_text(long long done, double elapsed) const {
  const bool terminal = settings_.is_terminal;
  std::string text = label_ + (terminal ? " " : ": ");
  if (total_ > 0) {
    const double fraction = std::clamp(double(done) / double(total_), 0.0, 1.0);
    if (terminal) {
      const int filled = int(fraction * settings_.bar_width);
      text += "[" + std::string(filled, '#') + std::string(settings_.bar_width - filled, '-') + "] ";
    }
    const int percent = int(fraction * 100);
    char numbers[64];
    if (terminal) {
      std::snprintf(numbers, sizeof numbers, "%3d%%  %lld/%lld", percent, done, total_);
    } else {
      std::snprintf(numbers, sizeof numbers, "%lld/%lld (%d%%)", done, total_, percent);
    }
    text += numbers;
  } else {
    text += std::to_string(done);
  }
  const std::string gap = terminal ? "  " : ", ";
  if (finished_) {
    if (total_ > 0 && done < total_) return text + gap + "stopped after " + format_duration(elapsed);
    return text + gap + "done in " + format_duration(elapsed);
  }
  text += gap + "elapsed " + format_duration(elapsed);
  if (total_ > 0) {
    if (done > 0 && elapsed > 0) {
      text += gap + "ETA " + format_duration(elapsed / double(done) * double(std::max(0LL, total_ - done)));
    } else {
      text += gap + "ETA --:--";
    }
  }
  return text;
}

void ProgressBar::print(long long done, double now) {
  const std::string text = status_text(done, now - start_);
  if (settings_.is_terminal) {
    *out_ << '\r' << text << "\x1b[K" << std::flush;  // ESC[K clears what a longer line left
  } else {
    *out_ << text << '\n' << std::flush;
  }
  printed_ = true;
  last_print_ = now;
}

void ProgressBar::update(long long done) {
  if (finished_) return;
  done_ = done;
  const double now = settings_.clock();
  const double interval = settings_.is_terminal ? settings_.redraw_interval_s : settings_.line_interval_s;
  const bool first_draw = settings_.is_terminal && !printed_;
  if (first_draw || now - last_print_ >= interval) print(done, now);
}

void ProgressBar::finish() {
  if (finished_) return;
  finished_ = true;
  print(done_, settings_.clock());
  if (settings_.is_terminal) *out_ << '\n' << std::flush;
}

}  // namespace tissu
