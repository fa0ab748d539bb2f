#pragma once
// The boom operator's schedule of conops-boom.csv (issue 9, item 2): the
// CONOPS approach with the boom columns. The boom stays stowed far out, is
// lowered to the trail position as the receiver closes, and in region C it
// tracks the receiver's receptacle (pointed at it, extended towards it). A
// pure function of the rig, the path and the options.

#include <Eigen/Core>
#include <vector>

#include "aar/flight_path.h"
#include "aar/rig.h"

namespace aar::flightpaths {

struct BoomScheduleOptions {
  double lower_start_range_m = 60.0;  ///< stowed beyond this range [m]
  double trail_range_m = 45.0;        ///< at the trail position from here in [m]
  double track_range_m = 38.0;        ///< tracking the receptacle from here in (region C) [m]
  double trail_pitch_deg = 30.0;      ///< trail position: elevation below the horizontal [deg]
  double trail_extension_m = 1.0;     ///< trail position: telescoped out [m]
  /// The receiver's receptacle, receiver frame [m]: on the C-12's cabin roof
  /// 1.5 m ahead of the reference point (just aft of the windscreen).
  Eigen::Vector3d receptacle_in_receiver{1.5, 0.0, 0.82};
};

/// The boom pose that points the boom at `target_in_tanker` and extends its
/// nozzle towards it, clamped to BoomPose's ranges.
BoomPose BoomPointedAt(const Eigen::Vector3d& target_in_tanker);

/// `samples` with every sample's boom set by the schedule (smoothstep in
/// range between the stages), rounded to the CSV precision.
std::vector<FlightSample> AddBoomSchedule(const StereoRig& rig, std::vector<FlightSample> samples,
                                          const BoomScheduleOptions& options = {});

}  // namespace aar::flightpaths
