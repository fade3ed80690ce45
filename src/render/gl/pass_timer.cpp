#include "render/gl/pass_timer.h"

#include "render/cpu_clock.h"
#include "render/gl/gl.h"

namespace tissu {

void PassTimer::enable(bool on) {
  enabled_ = on;
  times_.clear();
}

void PassTimer::start() {
  if (!enabled_) return;
  glFinish();
  cpu0_ = process_cpu_seconds();
  wall0_ = wall_seconds();
}

void PassTimer::lap(const char* name) {
  if (!enabled_) return;
  glFinish();
  const double cpu = process_cpu_seconds();
  const double wall = wall_seconds();
  RenderPassTime* entry = nullptr;
  for (RenderPassTime& t : times_) {
    if (t.pass == name) entry = &t;
  }
  if (entry == nullptr) {
    times_.push_back(RenderPassTime{name});
    entry = &times_.back();
  }
  entry->cpu_s += cpu - cpu0_;
  entry->wall_s += wall - wall0_;
  ++entry->count;
  cpu0_ = cpu;
  wall0_ = wall;
}

}  // namespace tissu
