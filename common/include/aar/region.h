#pragma once
// Flight-path regions of the thesis (section 3.7) and range bins (Tables 1-3).

#include <string>

namespace aar {

/// "A" for 70-175 m, "B" for 38-70 m, "C" for 32-38 m, "none" otherwise.
/// Lower bounds inclusive, upper bounds exclusive, except 175 m which is in A.
std::string RegionForRange(double range_m);

/// "20-60" for [20, 60) m, "60-110" for [60, 110] m, "none" otherwise.
std::string RangeBinForRange(double range_m);

}  // namespace aar
