#include "holds.h"

#include <algorithm>
#include <cmath>

#include "receiver_box.h"

namespace aar::flightpaths {

std::vector<Hold> FindHolds(const StereoRig& rig, const std::vector<FlightSample>& samples, double max_speed_mps,
                            double min_duration_s) {
  std::vector<double> range(samples.size());
  for (size_t i = 0; i < samples.size(); ++i) range[i] = RangeFromLeftCamera(rig, samples[i].tanker_from_receiver);
  auto still = [&](size_t i) {  // step i-1 -> i
    const double dt = samples[i].time_s - samples[i - 1].time_s;
    return std::abs(range[i] - range[i - 1]) <= max_speed_mps * dt;
  };
  std::vector<Hold> holds;
  size_t i = 0;
  while (i < samples.size()) {
    size_t j = i;
    while (j + 1 < samples.size() && still(j + 1)) ++j;
    const double duration = samples[j].time_s - samples[i].time_s;
    if (duration >= min_duration_s) {
      Hold hold;
      hold.first = i;
      hold.count = j - i + 1;
      double sum = 0.0;
      double lo = range[i];
      double hi = range[i];
      for (size_t k = i; k <= j; ++k) {
        sum += range[k];
        lo = std::min(lo, range[k]);
        hi = std::max(hi, range[k]);
      }
      hold.mean_range_m = sum / static_cast<double>(hold.count);
      hold.range_spread_m = hi - lo;
      hold.duration_s = duration;
      holds.push_back(hold);
    }
    i = j + 1;
  }
  return holds;
}

}  // namespace aar::flightpaths
