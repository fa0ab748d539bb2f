#include "aar/region.h"

namespace aar {

std::string RegionForRange(double range_m) {
  if (range_m >= 32.0 && range_m < 38.0) return "C";
  if (range_m >= 38.0 && range_m < 70.0) return "B";
  if (range_m >= 70.0 && range_m <= 175.0) return "A";
  return "none";
}

std::string RangeBinForRange(double range_m) {
  if (range_m >= 20.0 && range_m < 60.0) return "20-60";
  if (range_m >= 60.0 && range_m <= 110.0) return "60-110";
  return "none";
}

}  // namespace aar
