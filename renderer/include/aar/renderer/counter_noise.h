#pragma once
// Counter-based random numbers for the image effects' noise (the sensor
// model, the thermal detector): each value a pure function of a key and its
// counter (seed, stream, exposure, camera, sample), so every sample's noise
// is the same whatever the thread or the order it is drawn in.

#include <cmath>
#include <cstdint>
#include <numbers>

namespace aar {

/// splitmix64's finaliser (Steele, Lea and Flood, "Fast splittable
/// pseudorandom number generators", OOPSLA 2014): a bijective 64-bit mix.
inline uint64_t SplitMix64(uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

/// A key extended by one counter.
inline uint64_t Mix(uint64_t key, uint64_t value) { return SplitMix64(key ^ SplitMix64(value)); }

struct NormalPair {
  double first = 0.0;
  double second = 0.0;
};

/// Two independent standard normal numbers from 64 random bits (Box-Muller on
/// two 32-bit uniforms in (0, 1); the tails are cut at 6.7 sigma).
inline NormalPair Normals(uint64_t bits) {
  const double u1 = (static_cast<double>(bits >> 32) + 0.5) * 0x1p-32;
  const double u2 = (static_cast<double>(bits & 0xffffffffULL) + 0.5) * 0x1p-32;
  const double r = std::sqrt(-2.0 * std::log(u1));
  const double angle = 2.0 * std::numbers::pi * u2;
  return {r * std::cos(angle), r * std::sin(angle)};
}

}  // namespace aar
