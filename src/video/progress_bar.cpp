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

void ProgressBar::count_frames(long long total_frames, double end_time) {
  count_frames_ = true;
  total_frames_ = total_frames;
  end_time_ = end_time;
}

double ProgressBar::fraction() const {
  if (count_frames_) {
    if (end_time_ > 0.0) return std::clamp(time_ / end_time_, 0.0, 1.0);
    return total_frames_ > 0 ? std::clamp(double(frames_) / double(total_frames_), 0.0, 1.0) : 0.0;
  }
  return total_ > 0 ? std::clamp(double(done_) / double(total_), 0.0, 1.0) : 0.0;
}

bool ProgressBar::complete() const {
  return count_frames_ ? frames_ >= total_frames_ : total_ <= 0 || done_ >= total_;
}

// "135/300", or "frame=  45/120 time=1.500s" (at least 4 digits wide, as ffmpeg's).
std::string ProgressBar::count_text() const {
  char text[96];
  if (count_frames_) {
    const int width = std::max(4, int(std::to_string(total_frames_).size()));
    std::snprintf(text, sizeof text, "frame=%*lld/%lld time=%.3fs", width, frames_, total_frames_,
                  time_);
  } else if (total_ > 0) {
    std::snprintf(text, sizeof text, "%lld/%lld", done_, total_);
  } else {
    std::snprintf(text, sizeof text, "%lld", done_);
  }
  return text;
}

std::string ProgressBar::status_text(double elapsed) const {
  const bool terminal = settings_.is_terminal;
  const bool known_total = count_frames_ || total_ > 0;
  const double f = fraction();
  std::string text = label_ + (terminal ? " " : ": ");
  if (known_total) {
    const int percent = int(f * 100);
    char numbers[32];
    if (terminal) {
      const int filled = int(f * settings_.bar_width);
      text += "[" + std::string(filled, '#') + std::string(settings_.bar_width - filled, '-') + "] ";
      std::snprintf(numbers, sizeof numbers, "%3d%%  ", percent);
      text += numbers + count_text();
    } else {
      std::snprintf(numbers, sizeof numbers, " (%d%%)", percent);
      text += count_text() + numbers;
    }
  } else {
    text += count_text();
  }
  const std::string gap = terminal ? "  " : ", ";
  if (finished_) {
    return text + gap + (complete() ? "done in " : "stopped after ") + format_duration(elapsed);
  }
  text += gap + "elapsed " + format_duration(elapsed);
  if (!known_total) return text;
  double eta = -1.0;
  if (count_frames_) {
    if (f > 0.0 && elapsed > 0.0) eta = elapsed / f * (1.0 - f);
  } else if (done_ > 0 && elapsed > 0.0) {
    eta = elapsed / double(done_) * double(std::max(0LL, total_ - done_));
  }
  return text + gap + "ETA " + (eta >= 0.0 ? format_duration(eta) : std::string("--:--"));
}

void ProgressBar::print(double now) {
  const std::string text = status_text(now - start_);
  if (settings_.is_terminal) {
    *out_ << '\r' << text << "\x1b[K" << std::flush;  // ESC[K clears what a longer line left
  } else {
    *out_ << text << '\n' << std::flush;
  }
  printed_ = true;
  last_print_ = now;
}

void ProgressBar::maybe_print() {
  const double now = settings_.clock();
  const double interval = settings_.is_terminal ? settings_.redraw_interval_s : settings_.line_interval_s;
  const bool first_draw = settings_.is_terminal && !printed_;
  if (first_draw || now - last_print_ >= interval) print(now);
}

void ProgressBar::update(long long done) {
  if (finished_) return;
  done_ = done;
  maybe_print();
}

void ProgressBar::update_frames(long long frames, double time) {
  if (finished_) return;
  frames_ = frames;
  time_ = time;
  maybe_print();
}

void ProgressBar::finish() {
  if (finished_) return;
  finished_ = true;
  print(settings_.clock());
  if (settings_.is_terminal) *out_ << '\n' << std::flush;
}

}  // namespace tissu
