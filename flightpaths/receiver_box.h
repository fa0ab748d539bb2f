#pragma once
// The receiver as a box for the flight-path generators: how its corners
// project into the stereo rig's images for one pose, and the range from the
// left camera. Ranges are measured from the left camera centre to the
// receiver reference point (docs/frames.md); positions are in the tanker frame.

#include <Eigen/Core>
#include <vector>

#include "aar/pose.h"
#include "aar/rig.h"

namespace aar::flightpaths {

/// Conservative axis-aligned bounding box of the receiver in the receiver
/// frame (x forward, y left, z up): it holds the C-12 of scenes/c12.glb, whose
/// own box is x -7.89..5.45, y -8.31..8.31, z -0.82..2.89 m (aar-make-scenes
/// prints it; docs/scenes.md), with a margin.
struct ReceiverBox {
  Eigen::Vector3d min_m{-7.9, -8.4, -1.7};  ///< tail, right wing tip, belly [m]
  Eigen::Vector3d max_m{5.5, 8.4, 3.1};     ///< nose, left wing tip, fin top [m]

  /// The 8 corners in the receiver frame.
  std::vector<Eigen::Vector3d> Corners() const;
  Eigen::Vector3d Centre() const { return 0.5 * (min_m + max_m); }
};

/// How the box projects for one pose.
struct BoxVisibility {
  int corners_in_left = 0;     ///< corners projecting inside the left image (of 8)
  int corners_in_right = 0;    ///< same for the right image
  double min_margin_px = 0.0;  ///< smallest distance of a corner to an image border, both images; negative when outside
  bool reference_in_both = false;  ///< the reference point projects inside both images
  bool FullyInBoth() const { return corners_in_left == 8 && corners_in_right == 8; }
};

/// Projects the 8 box corners (posed by `tanker_from_receiver`) into both
/// cameras. A corner behind a camera counts as outside with margin -1e9.
BoxVisibility ComputeBoxVisibility(const StereoRig& rig, const ReceiverBox& box, const Pose& tanker_from_receiver);

/// Distance from the left camera centre to the receiver reference point [m].
double RangeFromLeftCamera(const StereoRig& rig, const Pose& tanker_from_receiver);

}  // namespace aar::flightpaths
