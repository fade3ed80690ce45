// The largest stable time step, found by bracketing and geometric bisection on any
// stability predicate (a simulation in `tissu stability`, a known threshold in tests).
#pragma once

#include <functional>
#include <vector>

namespace tissu {

struct BisectionOptions {
  double start = 1e-4;          // s, first step tried (clamped to [min, max])
  double min = 1e-7;            // s, smallest step tried
  double max = 1.0 / 30.0;      // s, largest step tried (one video frame)
  double precision = 0.1;       // stop when smallest unstable / largest stable <= 1 + precision
};

struct BisectionTrial {
  double dt;    // s
  bool stable;
};

struct BisectionResult {
  double largest_stable = 0.0;      // s; 0 when even `min` was unstable
  double smallest_unstable = 0.0;   // s; 0 when even `max` was stable
  bool stable_at_max = false;       // the limit is at least `max`
  bool unstable_at_min = false;     // the limit is below `min`
  std::vector<BisectionTrial> trials;  // in the order tried
};

// From `start`, doubles the step while stable (or halves it while unstable) to bracket the
// limit, then bisects the bracket geometrically (sqrt(lo * hi)) until hi / lo <= 1 + precision.
// Assumes stability is monotone in dt (stable below a threshold, unstable above); where it is
// not, the result is one stable/unstable boundary inside the first bracket found.
BisectionResult bisect_largest_stable(const std::function<bool(double)>& stable,
                                      const BisectionOptions& options);

}  // namespace tissu
