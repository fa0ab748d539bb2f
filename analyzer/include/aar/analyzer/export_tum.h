#pragma once
// TUM RGB-D trajectory files (`evo_ape tum truth.tum estimate.tum` reads
// them as they are): one line per frame, "t tx ty tz qx qy qz qw", with t
// the flight-path time [s], (tx, ty, tz) [m] and the unit quaternion (qw >= 0)
// of tanker_from_receiver: the receiver's pose in the tanker frame.
//
//   OUT/truth.tum      from the sidecars of the selected frames
//   OUT/estimate.tum   (with ExportOptions::run) the run's measured frames
//                      (status ok) among the selected ones

#include <string>
#include <vector>

#include "aar/analyzer/export_source.h"
#include "aar/pose.h"

namespace aar {

/// One "t tx ty tz qx qy qz qw" line (with newline), 9 decimals.
std::string TumLine(double time_s, const Pose& tanker_from_receiver);

ExportResult ExportTum(const ExportOptions& options);

}  // namespace aar
