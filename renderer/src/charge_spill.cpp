#include "aar/renderer/charge_spill.h"

#include <algorithm>
#include <cstddef>

namespace aar {
namespace {

// One column (stride apart from `first`), already smeared.
void BloomColumn(std::vector<double>& e, size_t first, size_t stride, int height, const ChargeSpillOptions& o) {
  std::vector<double> spill(height);  // each pixel's own excess that spills, half each way
  for (int y = 0; y < height; ++y) {
    double& v = e[first + y * stride];
    spill[y] = o.blooming * std::max(0.0, v - o.full_well_e);
    v = std::min(v, o.full_well_e);
  }
  // Downwards, then upwards: what a pixel cannot hold goes on in the same direction.
  double carry = 0.0;
  for (int y = 0; y < height; ++y) {
    double& v = e[first + y * stride];
    v += carry;
    const double over = std::max(0.0, v - o.full_well_e);
    v -= over;
    carry = over + 0.5 * spill[y];
  }
  carry = 0.0;
  for (int y = height - 1; y >= 0; --y) {
    double& v = e[first + y * stride];
    v += carry;
    const double over = std::max(0.0, v - o.full_well_e);
    v -= over;
    carry = over + 0.5 * spill[y];
  }
}

}  // namespace

void SpillCharge(std::vector<double>& electrons, int width, int height, int channels,
                 const ChargeSpillOptions& options) {
  if (options.blooming == 0.0 && options.smear == 0.0) return;
  const size_t stride = static_cast<size_t>(width) * channels;
  for (int x = 0; x < width; ++x) {
    for (int c = 0; c < channels; ++c) {
      const size_t first = static_cast<size_t>(x) * channels + c;
      if (options.smear > 0.0) {
        double sum = 0.0;
        for (int y = 0; y < height; ++y) sum += electrons[first + y * stride];
        const double add = options.smear * sum / height;
        for (int y = 0; y < height; ++y) electrons[first + y * stride] += add;
      }
      if (options.blooming > 0.0) BloomColumn(electrons, first, stride, height, options);
    }
  }
}

}  // namespace aar
