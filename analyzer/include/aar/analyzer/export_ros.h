#pragma once
// ROS CameraInfo calibration files (camera_calibration_parsers' YAML, as
// `camera_info_url` loads them): OUT/left.yaml and OUT/right.yaml from the
// dataset's calibration_ideal.yaml: K = M, D (plumb_bob, five zeros),
// R = R1/R2, P = P1/P2 (the right P carries Tx = -f b in P[0][3]).

#include <string>

#include "aar/analyzer/export_source.h"
#include "aar/stereo_calibration.h"

namespace aar {

/// The YAML text of one camera: `camera` is "left" or "right".
std::string CameraInfoYaml(const StereoCalibration& calibration, const std::string& camera);

ExportResult ExportRos(const ExportOptions& options);

}  // namespace aar
