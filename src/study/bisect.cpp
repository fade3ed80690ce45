#include "study/bisect.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace tissu {

BisectionResult bisect_largest_stable(const std::function<bool(double)>& stable,
                                      const BisectionOptions& options) {
  if (!(options.min > 0.0) || !(options.max >= options.min) || !(options.precision > 0.0)) {
    throw std::invalid_argument("bisection: need 0 < min <= max and precision > 0");
  }
  BisectionResult r;
  auto test = [&](double dt) {
    const bool ok = stable(dt);
    r.trials.push_back({dt, ok});
    return ok;
  };

  // Bracket: lo stable, hi unstable.
  double lo = 0.0, hi = 0.0;
  const double start = std::clamp(options.start, options.min, options.max);
  if (test(start)) {
    lo = start;
    while (lo < options.max) {
      const double next = std::min(2.0 * lo, options.max);
      if (test(next)) {
        lo = next;
      } else {
        hi = next;
        break;
      }
    }
    if (hi == 0.0) r.stable_at_max = true;
  } else {
    hi = start;
    while (hi > options.min) {
      const double next = std::max(0.5 * hi, options.min);
      if (test(next)) {
        lo = next;
        break;
      }
      hi = next;
    }
    if (lo == 0.0) r.unstable_at_min = true;
  }

  // Geometric bisection of the bracket.
  if (lo > 0.0 && hi > 0.0) {
    while (hi / lo > 1.0 + options.precision) {
      const double mid = std::sqrt(lo * hi);
      if (test(mid)) {
        lo = mid;
      } else {
        hi = mid;
      }
    }
  }
  r.largest_stable = lo;
  r.smallest_unstable = hi;
  return r;
}

}  // namespace tissu
