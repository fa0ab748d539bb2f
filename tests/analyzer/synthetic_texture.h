#pragma once
// A band-limited texture for synthetic stereo pairs of the sub-pixel and
// window-bias tests.

#include <cmath>
#include <random>
#include <vector>

namespace aar::test {

/// A band-limited texture (sums of sinusoids up to 0.25 cycles per pixel),
/// evaluated anywhere, so both images sample the same continuous surface.
class Texture {
 public:
  explicit Texture(unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> frequency(0.03, 0.25), phase(0.0, 2.0 * M_PI), angle(0.0, M_PI);
    for (int k = 0; k < 24; ++k) {
      const double f = frequency(rng), a = angle(rng);
      waves_.push_back({2.0 * M_PI * f * std::cos(a), 2.0 * M_PI * f * std::sin(a), phase(rng)});
    }
  }
  double operator()(double x, double y) const {
    double sum = 0.0;
    for (const Wave& w : waves_) sum += std::sin(w.kx * x + w.ky * y + w.phase);
    return 128.0 + 90.0 * sum / std::sqrt(static_cast<double>(waves_.size()));
  }

 private:
  struct Wave {
    double kx, ky, phase;
  };
  std::vector<Wave> waves_;
};

}  // namespace aar::test
