#pragma once
// A seeded stream of random numbers that is the same on every platform and
// compiler (std::mt19937 is, but std::uniform_real_distribution and
// std::normal_distribution are not): splitmix64 (Steele, Lea and Flood,
// "Fast splittable pseudorandom number generators", 2014) as a sequential
// generator, uniform numbers from its top 53 bits, normal ones by Box-Muller.

#include <cmath>
#include <cstdint>
#include <numbers>

namespace aar {

class RandomStream {
 public:
  explicit RandomStream(uint64_t seed) : state_(seed) {}

  uint64_t Next() {
    uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }

  /// Uniform in [0, 1).
  double Uniform() { return static_cast<double>(Next() >> 11) * 0x1.0p-53; }

  /// Uniform in [lo, hi).
  double Uniform(double lo, double hi) { return lo + (hi - lo) * Uniform(); }

  /// Standard normal (Box-Muller, one of the pair).
  double Normal() {
    const double u1 = 1.0 - Uniform(), u2 = Uniform();  // u1 in (0, 1]
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2);
  }

 private:
  uint64_t state_;
};

}  // namespace aar
