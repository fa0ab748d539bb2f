#pragma once
// Stereo calibration from chessboard image pairs (thesis 3.3 and 4.3).
//
// Pipeline: per image, findChessboardCorners + cornerSubPix; per camera,
// Zhang's method (cv::calibrateCamera); then cv::stereoCalibrate for
// right_from_left (R, T) and cv::stereoRectify for R1 R2 P1 P2 Q. Quality is
// reported the way the thesis does (Table 6: RMS re-projection and epipolar
// constraint error; Table 7: element-wise percent error of Q against the ideal
// Q), plus focal length and baseline errors.
//
// Nothing here needs truth: the board poses in the calib sidecars are never
// read. The ideal calibration is used only to report errors.

#include <array>
#include <cstddef>
#include <filesystem>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "aar/dataset.h"
#include "aar/opened_dataset.h"
#include "aar/stereo_calibration.h"

namespace aar {

/// Which lens model the calibration fits.
enum class DistortionModel {
  kAuto,     ///< CalibrateFromDataset: kBrownConrady when the dataset's rig.json gives its cameras lens distortion
             ///< (aar-rig/2 with "distortion"; the model, never the values, is read), else kPinhole; elsewhere kPinhole
  kPinhole,  ///< D1 = D2 = 0 (CALIB_FIX_K1..K3 | CALIB_ZERO_TANGENT_DIST), the renderer's pinhole cameras
  kBrownConrady,    ///< estimate k1 k2 p1 p2, k3 fixed at 0 (CALIB_FIX_K3): two radial terms, the default of ROS
                    ///< camera_calibration (--k-coefficients 2) and MATLAB's estimateCameraParameters; with boards
                    ///< that do not reach the image corners k3 trades off against k2
  kBrownConradyK3,  ///< estimate all of k1 k2 p1 p2 k3, OpenCV's default (the thesis)
};

/// "auto", "pinhole", "brown-conrady", "brown-conrady-k3" (the --distortion values).
DistortionModel ParseDistortionModel(const std::string& text);
const char* DistortionModelName(DistortionModel model);

struct CalibrationOptions {
  BoardSpec board;  ///< board geometry (thesis 3.3: 16x17 inner corners, 0.5 m squares); a calib sidecar's "board"
                    ///< overrides it in CalibrateFromDataset

  // Corner detection (cv::findChessboardCorners, then cv::cornerSubPix).
  bool adaptive_threshold = true;  ///< CALIB_CB_ADAPTIVE_THRESH
  bool normalize_image = false;    ///< CALIB_CB_NORMALIZE_IMAGE (histogram equalisation); off: on renders of steeply
                                   ///< tilted boards it makes detection fail (aar-render calib pairs 5 and 11)
  bool fast_check = false;  ///< CALIB_CB_FAST_CHECK: only speeds up rejecting images without a board; off because it
                            ///< can reject hard views
  int subpix_half_window_px = 5;  ///< cornerSubPix winSize (half the side): 5 -> an 11x11 window [px]; must stay below
                                  ///< the smallest imaged square
  int subpix_max_iterations = 100;  ///< cornerSubPix termination: iterations (OpenCV samples use 30)
  double subpix_epsilon_px = 1e-4;  ///< cornerSubPix termination: corner movement [px] (OpenCV samples use 0.001)

  // Calibration model. Both cameras are first calibrated alone (Zhang), then
  // stereoCalibrate refines (R, T) starting from those intrinsics.
  DistortionModel distortion = DistortionModel::kAuto;  ///< lens model (see DistortionModel)
  bool refine_intrinsics_in_stereo = true;  ///< true: CALIB_USE_INTRINSIC_GUESS (stereoCalibrate refines both cameras
                                            ///< jointly with R, T); false: CALIB_FIX_INTRINSIC (only R, T)
  /// true: CALIB_SAME_FOCAL_LENGTH in stereoCalibrate (one fx and one fy for
  /// both cameras; a matched pair). Boards at one depth cannot tell the
  /// focal-length ratio from the baseline's component along the optical axis.
  bool same_focal_length = false;
  int max_iterations = 100;     ///< Levenberg-Marquardt iterations (calibrateCamera and stereoCalibrate)
  double epsilon = 1e-12;       ///< Levenberg-Marquardt relative change to stop
  double rectify_alpha = -1.0;  ///< stereoRectify alpha: -1 = OpenCV's default scaling (f' = mean fy, no zoom), so
                                ///< Q is directly comparable with the ideal Q; 0..1 zooms to crop or keep all pixels

  size_t min_pairs = 5;            ///< fewest pairs with the board found in both images
  double min_pair_fraction = 0.5;  ///< fewest pairs with the board found, as a fraction of the pairs given

  /// Throws aar::Error naming the first value out of range.
  void Check() const;
};

/// One stereo pair given to the calibration.
struct StereoImagePair {
  std::string left_name;  ///< shown in messages, e.g. "calib/000003_left.png"
  std::string right_name;
  cv::Mat left;  ///< 8-bit, 1 or 3 channels (BGR as cv::imread returns)
  cv::Mat right;
};

/// Board detection in one pair, in the canonical corner order (see DetectBoardPair).
struct PairDetection {
  std::string left_name;
  std::string right_name;
  bool used = false;                      ///< board found in both images
  std::string reason;                     ///< why not used, e.g. "calib/000003_left.png: found no 16x17 chessboard"
  std::vector<cv::Point2f> left_corners;  ///< board x fastest (16 per row), 17 rows; empty when not used
  std::vector<cv::Point2f> right_corners;
};

/// Calibration errors against the ideal calibration (thesis Table 7).
struct IdealComparison {
  cv::Mat q_percent_error;              ///< 4x4 CV_64F, 100 |q - q_ideal| / |q_ideal|; 0 where q_ideal is 0
  double focal_error_percent = 0.0;     ///< 100 (f - f_ideal) / f_ideal with f = Q(2,3), the rectified focal length
  double baseline_error_percent = 0.0;  ///< 100 (|T| - b_ideal) / b_ideal
  double left_fx_error_percent = 0.0;   ///< 100 (M1(0,0) - fx_ideal) / fx_ideal
  double right_fx_error_percent = 0.0;  ///< 100 (M2(0,0) - fx_ideal) / fx_ideal
  double left_principal_point_error_px = 0.0;  ///< |(cx, cy) of M1 - ideal| [px]
  /// |(-Q(0,3), -Q(1,3)) - ideal| [px]. Not only the cameras' principal point
  /// error: stereoRectify turns rect_left by R1 to align x with the estimated
  /// baseline T, and a T direction off by a few tenths of a degree moves the
  /// rectified principal point by a few pixels (what thesis Table 7's Q(0,3) shows).
  double rectified_principal_point_error_px = 0.0;
  double rotation_error_deg = 0.0;            ///< angle of R * R_ideal^T (right_from_left rotation) [deg]
  double baseline_direction_error_deg = 0.0;  ///< angle between T and T_ideal [deg]
  double rectification_angle_deg =
      0.0;  ///< angle of R1 (rect_left against left); the ideal's is 0 for a parallel rig [deg]
  std::array<double, 5> left_distortion_error{};   ///< D1 - D1_ideal (k1 k2 p1 p2 k3)
  std::array<double, 5> right_distortion_error{};  ///< D2 - D2_ideal
  /// Largest distance, over every 4th pixel of the image, between where the
  /// estimated and the ideal calibration put a pixel's ray (undistortPoints
  /// with M1, D1 against the ideal's, in the ideal's pixels): the intrinsics'
  /// and the distortion's errors together, as rectification sees them [px].
  double left_ray_error_max_px = 0.0;
  double right_ray_error_max_px = 0.0;  ///< the same for M2, D2
};

struct CalibrationResult {
  StereoCalibration calibration;
  cv::Mat E, F;                      ///< essential and fundamental matrices (3x3 CV_64F), x_r^T E x_l = 0
  double rms_reprojection_px = 0.0;  ///< stereoCalibrate's return value (thesis Table 6, "RMS re-projection")
  double left_rms_px = 0.0;          ///< calibrateCamera's return for the left camera alone
  double right_rms_px = 0.0;         ///< same for the right camera
  /// Mean distance from each corner to its epipolar line, averaged over both
  /// images: for undistorted corner pixels p_l, p_r (homogeneous) and
  /// l_r = F p_l, l_l = F^T p_r,
  ///   e = 1/N sum_i ( |p_r^T F p_l| / ||(l_r0, l_r1)|| + |p_l^T F^T p_r| / ||(l_l0, l_l1)|| ) / 2   [px]
  /// over every corner of every used pair. The thesis (3.3) reports the
  /// constraint p1^T E p2; OpenCV's stereo_calib sample, which prints the
  /// thesis's "average epipolar err", sums the two distances (2 e).
  double epipolar_error_px = 0.0;
  double epipolar_algebraic = 0.0;  ///< 1/N sum_i |p_r^T F p_l| with pixel coordinates (F as stereoCalibrate scales it)
  size_t corner_count = 0;          ///< N: corners per image summed over the used pairs
  size_t used_pairs = 0;
  bool distortion_estimated = false;  ///< D1, D2 were fitted (Brown-Conrady), not fixed at zero
  /// Depth of the board's centre in the left camera (its calibrateCamera
  /// pose), nearest and farthest over the used pairs [m]. Boards that all lie
  /// at one depth z leave the baseline's component along the optical axis
  /// (T_z) and the ratio of the two focal lengths nearly interchangeable: the
  /// right camera moved T_z forward scales its image of the board by
  /// T_z / z, as a focal length larger by that fraction does. An error in
  /// T_z turns the re-projected scene by about T_z / b about the camera's
  /// vertical axis (docs/analysis.md, step 1).
  double board_depth_min_m = 0.0, board_depth_max_m = 0.0;
  bool same_focal_length = false;               ///< CalibrationOptions::same_focal_length was set
  std::vector<PairDetection> pairs;             ///< every pair given, in order, with status
  std::optional<IdealComparison> versus_ideal;  ///< when an ideal calibration was given / found

  /// A few lines for logs: pairs used and rejected (with reasons), RMS,
  /// epipolar error and the errors against the ideal.
  std::string BriefReport() const;
};

/// Detects the board's inner corners in one image (gray or BGR) and refines
/// them to sub-pixel; nullopt when the whole grid is not found. Corners are in
/// OpenCV's order, not yet canonical.
std::optional<std::vector<cv::Point2f>> DetectBoardCorners(const cv::Mat& image, const CalibrationOptions& options);

/// Detects the board in both images of a pair and puts the corners in the
/// canonical order. findChessboardCorners may return a grid mirrored or
/// rotated by 180 degrees; without truth we fix it so that (1) the grid is
/// right-handed in the image (row direction x column direction points into
/// the image, as for a board facing the camera with its z axis away from it:
/// cross((c[n-1]-c[0]), (c[last row start]-c[0])) > 0 in (u right, v down)),
/// reversing each row otherwise, and (2) in the left image the first corner is
/// the top-left-most (smallest u + v) of the two candidates c[0], c[last];
/// the right image takes whichever of its two orders lies closer to the left
/// corners (least summed squared displacement), so a pair never disagrees even
/// for a board rolled near 45 degrees. For the usual upright board this puts
/// corner 0 at the board origin (board frame, docs/frames.md).
PairDetection DetectBoardPair(const StereoImagePair& pair, const CalibrationOptions& options);

/// Calibrates from detections (used pairs only); throws aar::Error when fewer
/// than options.min_pairs (or min_pair_fraction) pairs were found, naming
/// `source` (a dataset folder or "images").
CalibrationResult CalibrateFromDetections(std::vector<PairDetection> pairs, cv::Size image_size,
                                          const CalibrationOptions& options,
                                          const std::optional<StereoCalibration>& ideal, const std::string& source);

/// Detects and calibrates from in-memory pairs; all images must share one size.
CalibrationResult CalibrateFromImages(const std::vector<StereoImagePair>& pairs, const CalibrationOptions& options,
                                      const std::optional<StereoCalibration>& ideal = std::nullopt);

/// Reads every calibration pair of `dataset` (its sidecar's board, when
/// recorded, replaces options.board), then calibrates (options.distortion
/// kAuto resolved from the dataset's rig.json). Errors are compared with
/// the dataset's calibration_ideal.yaml when present (else
/// with the ideal calibration of its rig.json when present). Throws
/// aar::Error naming the file for a missing, changed or undecodable image or
/// sidecar, and naming the dataset and the count found when too few pairs
/// show the board.
CalibrationResult CalibrateFromDataset(const OpenedDataset& dataset, const CalibrationOptions& options);

/// Element-wise percent error 100 |q - q_ideal| / |q_ideal| (thesis Table 7);
/// 0 where q_ideal is exactly 0. Both 4x4; returns 4x4 CV_64F.
cv::Mat QPercentError(const cv::Mat& q, const cv::Mat& q_ideal);

/// Focal, baseline, principal point and Q errors of `estimated` against `ideal`.
IdealComparison CompareToIdeal(const StereoCalibration& estimated, const StereoCalibration& ideal);

}  // namespace aar
