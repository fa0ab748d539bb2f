#pragma once
// Calibration-board poses (thesis 3.3, Figure 10): a fixed, deterministic set
// of tilted board poses behind the tanker, each with the whole board (border
// included) inside both images.

#include <vector>

#include "aar/dataset.h"
#include "aar/pose.h"
#include "aar/rig.h"

namespace aar {

struct CalibPoseOptions {
  double min_distance_m = 15.0;  ///< closest board-centre distance along the left optical axis [m]
  double border_m = 0.5;         ///< white border around the squares [m]
  double margin_px = 12.0;       ///< keep the board this far inside each image [px]
  /// Every tilt is placed again with its centre at each of these distances
  /// along the left optical axis [m] (empty: none, the thesis's single set).
  /// Boards at one distance leave the cameras' focal-length ratio and the
  /// baseline's component along the optical axis nearly indistinguishable
  /// (both scale one image against the other); more distances separate them.
  std::vector<double> far_distances_m;
  /// Eight more poses, last: the board pushed towards each image corner and
  /// edge midpoint (at the nearest distance where it fits, tilted 10 deg to
  /// face the optical axis), so that the image periphery, where lens
  /// distortion is largest, has corners to fit. Off by default (the thesis's set).
  bool corner_boards = false;
  BoardSpec board;
};

/// The board's outline corners (border included) in the board frame.
std::vector<Eigen::Vector3d> BoardOutline(const CalibPoseOptions& options);

/// Twelve poses tanker_from_board: tilts of up to 30 degrees about the board's
/// x and y axes and up to 15 degrees about its normal, each pushed back from
/// `min_distance_m` in 0.25 m steps until the outline fits both images; then
/// the same twelve tilts at each of far_distances_m; then, with corner_boards,
/// the eight periphery poses.
std::vector<Pose> CalibrationBoardPoses(const StereoRig& rig, const CalibPoseOptions& options = {});

}  // namespace aar
