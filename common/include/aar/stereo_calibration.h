#pragma once
// Stereo calibration in OpenCV's terms, stored as an OpenCV FileStorage YAML
// file with the nodes M1 D1 M2 D2 R T R1 R2 P1 P2 Q and image_size
// (docs/dataset-format.md). R, T are right_from_left; R1, R2 rotate the left
// and right camera frames into the rectified frames; Q maps (u, v, disparity, 1)
// in the rectified left image to homogeneous points in the rect_left frame.

#include <filesystem>
#include <opencv2/core.hpp>
#include <string>

#include "aar/rig.h"

namespace aar {

struct StereoCalibration {
  cv::Size image_size;
  cv::Mat M1, D1, M2, D2;  ///< camera matrices (3x3) and distortion (1x5), CV_64F
  cv::Mat R, T;            ///< right_from_left rotation (3x3) and translation (3x1) [m]
  cv::Mat R1, R2, P1, P2;  ///< rectification rotations (3x3) and projections (3x4)
  cv::Mat Q;               ///< 4x4 disparity-to-depth matrix
};

/// The exact calibration implied by a rig; requires the two cameras to be
/// parallel with identical pinhole intrinsics, as in scenes/rig.json, so that
/// rectification is the identity. D1, D2 are the cameras' lens distortion
/// (zero for a pinhole rig; the two lenses may differ): undistortion then maps
/// each image onto the ideal pinhole, which R1 = R2 = I leaves rectified.
/// Throws aar::Error otherwise.
StereoCalibration IdealCalibration(const StereoRig& rig);

/// OpenCV FileStorage YAML text for a calibration.
std::string CalibrationToYaml(const StereoCalibration& calibration);

/// Writes a calibration atomically.
void WriteCalibration(const std::filesystem::path& path, const StereoCalibration& calibration);

/// Throws aar::Error prefixed by `where` when a calibration cannot re-project:
/// non-positive focal lengths in M1, M2 or P1, or a Q without focal length
/// Q(2,3) or inverse baseline Q(3,2).
void CheckCalibration(const StereoCalibration& calibration, const std::string& where);

/// Reads and validates a calibration file (calibration_yaml.h's strict reader,
/// never OpenCV's parser); throws aar::Error naming the file, the line when
/// known, and the missing or malformed node.
StereoCalibration ReadCalibration(const std::filesystem::path& path);
/// The same for a calibration file's text, read from `where`.
StereoCalibration ParseCalibration(const std::string& text, const std::string& where);

}  // namespace aar
