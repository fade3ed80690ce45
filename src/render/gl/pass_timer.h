// Per-pass CPU and wall times for profiling the renderer. When enabled, lap() waits for
// the GL to finish the work issued so far (glFinish) and charges the time since the
// previous lap to the named pass. Disabled, lap() does nothing.
#pragma once

#include <string>
#include <vector>

#include "render/renderer.h"

namespace tissu {

class PassTimer {
 public:
  void enable(bool on);
  bool enabled() const { return enabled_; }
  // Starts timing (call before the first pass of a frame).
  void start();
  // Ends the pass `name`: glFinish(), then records the time since start() or the last lap.
  void lap(const char* name);
  const std::vector<RenderPassTime>& times() const { return times_; }

 private:
  bool enabled_ = false;
  double cpu0_ = 0.0, wall0_ = 0.0;
  std::vector<RenderPassTime> times_;
};

}  // namespace tissu
