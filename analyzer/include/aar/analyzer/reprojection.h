#pragma once
// Re-projection of a disparity map to a point cloud in the tanker frame
// (thesis 3.5, equations 1-3).

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstddef>
#include <opencv2/core.hpp>
#include <vector>

#include "aar/analyzer/subpixel.h"
#include "aar/stereo_calibration.h"

namespace aar {

struct ReprojectionOptions {
  double min_depth_m =
      1e-6;  ///< points with depth (z in rect_left) at or below this are dropped (behind the camera) [m]
  double max_depth_m = 750.0;  ///< points deeper than this are dropped (thesis 3.5: background) [m]
  size_t keep_one_in =
      8;  ///< decimation: keep valid points 0, k, 2k, ... in row-major order (thesis 3.5: 8); 1 keeps all
  /// When > 0, the decimation step is raised to floor(valid pixels /
  /// target_points) when that is larger than keep_one_in, so that a near
  /// receiver gives about this many points and a far one keeps all of its few.
  /// Valid pixels are those that pass the depth filter (a textured background
  /// beyond max_depth_m does not count).
  size_t target_points = 0;
  /// When > 0, points deeper than this times the median depth of the points
  /// that pass the depth filter are dropped as well: a GT-free range gate
  /// against the wrong matches of a textured background (terrain), which
  /// otherwise lie hundreds of metres behind a receiver at 32-175 m; the
  /// receiver's own depth spans a few per cent [ratio]. 0 = off (the thesis;
  /// the default preset uses 1.5).
  double max_depth_over_median = 0.0;
  /// The matcher's own mean error (MatcherRoundingBiasPx(): StereoBM's
  /// rounding), subtracted from its disparities; a refined disparity starts
  /// from the corrected value and does not carry that error [px].
  double matcher_bias_px = 0.0;
  /// Subtracted from every disparity used by eq. 1, refined or not [px]. 0
  /// reproduces the thesis's plain re-projection.
  double disparity_offset_px = 0.0;
};

/// The sensed point cloud of one frame.
struct SensedCloud {
  std::vector<Eigen::Vector3d> points_in_tanker;  ///< kept points, row-major pixel order [m]
  size_t valid_count = 0;               ///< points that passed the disparity and depth filters, before decimation
  size_t kept_count = 0;                ///< points_in_tanker.size()
  size_t refine_rejected = 0;           ///< decimated points the sub-pixel refiner rejected
  std::vector<Eigen::Vector3d> pixels;  ///< (u, v, disparity) of each kept point in rect_left [px]
};

/// Re-projects a CV_16S fixed-point disparity map (disparity * 16, as
/// ComputeDisparity returns; `invalid_value16` marks pixels without a
/// disparity) to the tanker frame:
///
///   [X Y Z W]^T = Q [u v d 1]^T, d = disparity16 / 16        (thesis eq. 1)
///   point_in_rect_left = (X, Y, Z) / W
///   point_in_left      = R1^T point_in_rect_left              (undo rectification)
///   point_in_tanker    = tanker_from_left * point_in_left     (thesis eqs. 2-3)
///
/// Eq. 1 is evaluated in double per valid pixel (the same product as
/// cv::reprojectImageTo3D with handleMissingValues = false, without its float
/// output image). Dropped: invalid pixels (disparity16 <= invalid_value16),
/// non-finite results, depth z <= min_depth_m or z > max_depth_m (thesis 3.5).
/// The survivors are decimated one in keep_one_in (or the target_points
/// step), in row-major order. With a `refiner`, each kept disparity is then
/// refined (SubpixelRefiner::Refine; points it rejects are dropped) and the
/// point re-projected from the refined left column and disparity. `origin`
/// is the rectified-image pixel of the map's top-left (a region of the image).
SensedCloud Reproject(const cv::Mat& disparity16, int invalid_value16, const StereoCalibration& calibration,
                      const Eigen::Isometry3d& tanker_from_left, const ReprojectionOptions& options,
                      const SubpixelRefiner* refiner = nullptr, cv::Point origin = {0, 0});

}  // namespace aar
