#pragma once
// Holds in a flight path: runs of samples in which the receiver is
// near-stationary in range (thesis Figures 20-23's groupings at ~49, 34, 32 m).

#include <cstddef>
#include <vector>

#include "aar/flight_path.h"
#include "aar/rig.h"

namespace aar::flightpaths {

/// A hold: a run of consecutive samples in which the receiver is near-stationary.
struct Hold {
  size_t first = 0;             ///< index of the first sample
  size_t count = 0;             ///< number of samples
  double mean_range_m = 0.0;    ///< [m]
  double range_spread_m = 0.0;  ///< max - min range over the hold [m]
  double duration_s = 0.0;      ///< time from first to last sample [s]
};

/// Maximal runs of consecutive samples in which every step changes the range
/// by at most `max_speed_mps` * dt, lasting at least `min_duration_s`. The
/// default 2 cm/s lies above the wander's range rate (< 1.3 cm/s) and far
/// below the approach speeds.
std::vector<Hold> FindHolds(const StereoRig& rig, const std::vector<FlightSample>& samples, double max_speed_mps = 0.02,
                            double min_duration_s = 5.0);

}  // namespace aar::flightpaths
