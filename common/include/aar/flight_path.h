#pragma once
// Flight-path CSV files (flightpaths/*.csv, documented in docs/dataset-format.md):
// header `time_s,x_m,y_m,z_m,roll_deg,pitch_deg,yaw_deg`, one sample per line,
// the receiver reference point and attitude in the tanker body frame.

#include <filesystem>
#include <string>
#include <vector>

#include "aar/pose.h"

namespace aar {

inline constexpr const char* kFlightPathHeader = "time_s,x_m,y_m,z_m,roll_deg,pitch_deg,yaw_deg";

struct FlightSample {
  double time_s = 0.0;        ///< sample time [s]
  Pose tanker_from_receiver;  ///< receiver pose in the tanker frame
};

/// Reads and validates a flight-path CSV. Throws aar::Error naming the file
/// and line on a missing file, wrong header, wrong column count, a field that
/// is not a finite number, or an empty path.
std::vector<FlightSample> ReadFlightPath(const std::filesystem::path& path);

/// Formats samples as CSV text with the canonical header (fixed precision).
std::string FormatFlightPath(const std::vector<FlightSample>& samples);

/// `sample` rounded to FormatFlightPath's precision (time 1 ms, metres and
/// degrees 1e-4), so that formatting and reading it back returns it exactly.
FlightSample RoundToCsvPrecision(FlightSample sample);

}  // namespace aar
