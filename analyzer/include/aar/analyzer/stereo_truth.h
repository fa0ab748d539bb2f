#pragma once
// The sensed cloud measured against the renderer's depth truth (datasets
// rendered with --depth): the disparity error of every sensed point, by
// fractional disparity, and the fraction of points that are not on the
// receiver's surface.
//
// The true disparity of a sensed point at rectified left pixel (u, v) is the
// one the run's calibration implies for the true surface there: the ray of
// (u, v) (P1, R1) meets the left image at a pixel (M1, no distortion) where the
// depth image gives the true point; its rectified depth z gives
// d_true = (Q(2,3) / z - Q(3,3)) / Q(3,2). Depth is interpolated bilinearly
// where the four neighbouring pixels are all receiver, else taken from the
// nearest pixel.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstddef>
#include <filesystem>
#include <opencv2/core.hpp>
#include <optional>
#include <vector>

#include "aar/stereo_calibration.h"

namespace aar {

/// One camera's truth images of one frame.
struct DepthTruth {
  cv::Mat depth_m;  ///< CV_32F, metres along the camera's optical axis, 0 where no surface
  cv::Mat ids;      ///< CV_8U object ids: 0 sky, 1 receiver, 2 tanker, 3 board, 4 ground, 5 cloud deck
};

/// Reads a depth EXR (channel Y, or Z in older datasets) and its id mask PNG
/// (either camera); errors name the file.
DepthTruth ReadDepthTruth(const std::filesystem::path& depth_exr, const std::filesystem::path& mask_png);

inline constexpr int kReceiverId = 1;
inline constexpr size_t kFractionBins = 8;  ///< bins of the true disparity's fractional part, width 1/8 px

struct StereoTruthOptions {
  /// A point on the receiver whose disparity errs by more than this is off
  /// the surface [px] (at 35 m, 0.5 px is about 1.3 m of depth).
  double off_surface_px = 0.5;
  /// The true pose: with it, the points on the receiver whose true point lies
  /// on a propeller blade are counted (OnPropellerBlade).
  std::optional<Eigen::Isometry3d> rect_left_from_receiver;
};

/// Whether a point of the receiver (receiver frame) lies where only the
/// propeller blades are (common/include/aar/propeller.h, scenes/c12.cpp): in
/// a slab of +-0.12 m about a disc's plane (the blades' own +-0.09 m and the
/// depth truth's interpolation), between 0.35 m (beyond the spinner and the
/// nacelle's cowling in that slab) and 1.30 m (the tip circle and 5 cm) from
/// its axis. The receiver has no other surface there, so on a receiver
/// without propellers nothing passes.
bool OnPropellerBlade(const Eigen::Vector3d& point_in_receiver);

/// Sums over the sensed points of one frame (or of many: Add).
struct StereoTruthStats {
  size_t points = 0;           ///< sensed points compared
  size_t off_receiver = 0;     ///< points whose pixel is not on the receiver in the truth (halo, background)
  size_t off_surface = 0;      ///< off_receiver plus receiver points beyond off_surface_px
  size_t on_receiver = 0;      ///< points on the receiver (the disparity statistics use these)
  size_t on_propellers = 0;    ///< of on_receiver, points on a propeller blade (with the true pose)
  size_t propellers_kept = 0;  ///< of on_propellers, points the registration kept (the propeller mask's leftover)
  double error_sum_px = 0.0;
  double error_squared_sum_px2 = 0.0;
  std::array<size_t, kFractionBins> bin_count{};
  std::array<double, kFractionBins> bin_error_sum_px{};

  double MeanErrorPx() const { return on_receiver ? error_sum_px / static_cast<double>(on_receiver) : 0.0; }
  double RmsErrorPx() const;
  double OffSurfaceFraction() const {
    return points ? static_cast<double>(off_surface) / static_cast<double>(points) : 0.0;
  }
  void Add(const StereoTruthStats& other);
};

/// Compares sensed points (u, v, disparity in rect_left, as SensedCloud::pixels) with the truth.
/// With `true_points_in_rect_left`, also returns the true point of every
/// sensed point on the receiver (rect_left frame) [m]: the ideal cloud at the
/// same pixels, which isolates registration from stereo error. With
/// `true_disparity_px`, also the true disparity of every pixel (NaN where
/// the pixel is not on the receiver), one per pixel.
/// With `on_propellers`, also the indices of the pixels counted in
/// on_propellers, ascending.
StereoTruthStats CompareWithTruth(const std::vector<Eigen::Vector3d>& pixels, const DepthTruth& truth,
                                  const StereoCalibration& calibration, const StereoTruthOptions& options = {},
                                  std::vector<Eigen::Vector3d>* true_points_in_rect_left = nullptr,
                                  std::vector<double>* true_disparity_px = nullptr,
                                  std::vector<size_t>* on_propellers = nullptr);

}  // namespace aar
