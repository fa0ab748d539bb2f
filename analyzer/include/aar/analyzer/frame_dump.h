#pragma once
// `aar-analyze run --dump-frames LIST`: what one frame's analysis saw and
// did, for looking at (docs/analysis.md, "Frame dumps"). Per listed frame,
// into RUN/frames/:
//
//   NNNNNN_disparity.png   the rectified-left disparity, colour-mapped (turbo,
//                          the map's smallest to largest disparity), black where none
//   NNNNNN_sensed.ply      the sensed cloud given to ICP, tanker frame [m]
//   NNNNNN_model.ply       the reference model at the estimated pose, tanker frame [m]
//   NNNNNN_overlay.png     the left image with the registered model's points
//                          projected by the run's calibration (green), and the
//                          receiver origin at the estimate (green cross) and truth (red cross)
//   NNNNNN_points.csv      every sensed point's rectified-left pixel and disparity
//                          as registered (refined, corrected), and with depth
//                          truth its true disparity: u_px,v_px,disparity_px,true_disparity_px
//
// A frame without an estimate gets the disparity and the cloud when it got
// that far, and no model or overlay.

#include <Eigen/Geometry>
#include <filesystem>
#include <opencv2/core.hpp>
#include <optional>
#include <vector>

#include "aar/lens.h"

namespace aar {

/// Filled by FrameAnalyzer::Analyze when asked for.
struct FrameDump {
  cv::Mat left_bgr;                               ///< the left image as read
  cv::Mat disparity16;                            ///< the last disparity map (CV_16S, disparity * 16), of `region`
  cv::Rect region;                                ///< where disparity16 lies in the rectified left image
  int invalid_value16 = -16;                      ///< marks pixels without disparity
  std::vector<Eigen::Vector3d> sensed_in_tanker;  ///< the cloud given to ICP [m]
  /// The sensed points' (u, v, disparity) in the rectified left image as
  /// registered, and their true disparities (NaN: not on the receiver;
  /// empty without depth truth) [px].
  std::vector<Eigen::Vector3d> pixels;
  std::vector<double> true_disparity_px;
  std::optional<Eigen::Isometry3d> tanker_from_receiver;  ///< the estimate, when registered
  Eigen::Isometry3d tanker_from_receiver_truth = Eigen::Isometry3d::Identity();
};

/// What the overlay needs to project receiver points into the left image.
struct DumpProjection {
  Eigen::Matrix3d left_camera_matrix;                     ///< M1 of the run's calibration
  BrownConrady left_distortion;                           ///< D1 of the run's calibration
  Eigen::Isometry3d left_from_tanker;                     ///< inverse(tanker_from_left)
  std::vector<Eigen::Vector3d> model_points_in_receiver;  ///< the reference model
};

/// Colour-mapped disparity (BGR, full image size `image_size`; outside `region` black).
cv::Mat ColourDisparity(const FrameDump& dump, const cv::Size& image_size);

/// The left image with the registered model drawn on it; empty without an estimate.
cv::Mat OverlayModel(const FrameDump& dump, const DumpProjection& projection);

/// Writes the files above for frame `index` into `dir` (created).
void WriteFrameDump(const std::filesystem::path& dir, size_t index, const FrameDump& dump,
                    const DumpProjection& projection);

}  // namespace aar
