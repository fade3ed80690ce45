// Seeded random numbers that are the same on every platform: std::mt19937_64's raw output
// is specified by the standard, the std:: distributions are not, so the mapping is ours.
#pragma once

#include <cstdint>
#include <random>

namespace tissu {

class PortableRandom {
 public:
  explicit PortableRandom(uint64_t seed) : engine_(seed) {}

  // Uniform in [0, 1), 53 random bits.
  double uniform() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }

  // Uniform in [lo, hi).
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }

  // Uniform integer in [0, n); n > 0. The modulo bias is below 2^-40 for n < 2^24.
  uint64_t below(uint64_t n) { return engine_() % n; }

 private:
  std::mt19937_64 engine_;
};

}  // namespace tissu
