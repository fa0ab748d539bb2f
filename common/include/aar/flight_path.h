#pragma once
// Flight-path CSV files (flightpaths/*.csv, documented in docs/dataset-format.md):
// header `time_s,x_m,y_m,z_m,roll_deg,pitch_deg,yaw_deg`, one sample per line,
// the receiver reference point and attitude in the tanker body frame;
// optionally three more columns `boom_pitch_deg,boom_roll_deg,boom_extension_m`,
// the tanker's boom (boom.h).

#include <Eigen/Geometry>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "aar/boom.h"
#include "aar/pose.h"

namespace aar {

inline constexpr const char* kFlightPathHeader = "time_s,x_m,y_m,z_m,roll_deg,pitch_deg,yaw_deg";
/// The header of a path that also poses the boom.
inline constexpr const char* kFlightPathBoomHeader =
    "time_s,x_m,y_m,z_m,roll_deg,pitch_deg,yaw_deg,boom_pitch_deg,boom_roll_deg,boom_extension_m";

struct FlightSample {
  double time_s = 0.0;        ///< sample time [s]
  Pose tanker_from_receiver;  ///< receiver pose in the tanker frame
  /// The boom's pose: set on every sample of a path with the boom columns,
  /// on none of a 7-column path.
  std::optional<BoomPose> boom;
};

/// Reads and validates a flight-path CSV. Throws aar::Error naming the file
/// and line on a missing file, wrong header (neither kFlightPathHeader nor
/// kFlightPathBoomHeader), wrong column count, a field that is not a finite
/// number, a boom value outside BoomPose's ranges, or an empty path.
std::vector<FlightSample> ReadFlightPath(const std::filesystem::path& path);
/// The same for the text of a flight-path file called `name` in the messages.
std::vector<FlightSample> ParseFlightPath(const std::string& text, const std::string& name);

/// Throws aar::Error naming `where` and the first pair of samples whose
/// times do not increase: motion over an exposure (TankerFromReceiverAt)
/// needs the path's clock.
void CheckTimesIncrease(const std::vector<FlightSample>& path, const std::string& where);

/// The receiver's pose at `time_s` on the path's clock (times increasing,
/// CheckTimesIncrease): between the two samples around it, position linear
/// and attitude spherical-linear (constant velocity and rate over the
/// interval); before the first or after the last sample, extrapolated from
/// the first or last interval. A one-sample path does not move.
Eigen::Isometry3d TankerFromReceiverAt(const std::vector<FlightSample>& path, double time_s);

/// Formats samples as CSV text with the canonical header (fixed precision);
/// with the boom columns when the first sample has a boom (then every sample
/// must have one, or aar::Error is thrown).
std::string FormatFlightPath(const std::vector<FlightSample>& samples);

/// `sample` rounded to FormatFlightPath's precision (time 1 ms, metres and
/// degrees 1e-4), so that formatting and reading it back returns it exactly.
FlightSample RoundToCsvPrecision(FlightSample sample);

}  // namespace aar
