#include "aar/analyzer/calibration.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "aar/analyzer/dataset_image.h"
#include "aar/analyzer/disparity.h"
#include "aar/error.h"
#include "aar/text.h"

namespace aar {
namespace {

std::string BoardName(const BoardSpec& board) {
  return std::to_string(board.inner_corners_x) + "x" + std::to_string(board.inner_corners_y);
}

/// Reverses every row (board x) when the grid is left-handed in the image.
void MakeRightHanded(std::vector<cv::Point2f>& c, int nx, int ny) {
  const cv::Point2f row = c[nx - 1] - c[0];
  const cv::Point2f col = c[static_cast<size_t>(ny - 1) * nx] - c[0];
  if (static_cast<double>(row.x) * col.y - static_cast<double>(row.y) * col.x >= 0) return;
  for (int j = 0; j < ny; ++j) std::reverse(c.begin() + j * nx, c.begin() + (j + 1) * nx);
}

double SumSquaredDistance(const std::vector<cv::Point2f>& a, const std::vector<cv::Point2f>& b) {
  double sum = 0.0;
  for (size_t i = 0; i < a.size(); ++i) {
    const double dx = a[i].x - b[i].x, dy = a[i].y - b[i].y;
    sum += dx * dx + dy * dy;
  }
  return sum;
}

std::vector<cv::Point3f> BoardObjectPoints(const BoardSpec& board) {
  // Board frame (docs/frames.md): corner (i, j) at (square i, square j, 0).
  std::vector<cv::Point3f> points;
  for (int j = 0; j < board.inner_corners_y; ++j) {
    for (int i = 0; i < board.inner_corners_x; ++i) {
      points.emplace_back(static_cast<float>(board.square_m * i), static_cast<float>(board.square_m * j), 0.0f);
    }
  }
  return points;
}

/// Thesis 3.3: average epipolar constraint error over all corners (formula in
/// CalibrationResult::epipolar_error_px).
void EpipolarErrors(const std::vector<PairDetection>& pairs, const StereoCalibration& c, const cv::Mat& f,
                    CalibrationResult& result) {
  const cv::Matx33d F(f);
  double distance_sum = 0.0, algebraic_sum = 0.0;
  size_t n = 0;
  for (const PairDetection& pair : pairs) {
    if (!pair.used) continue;
    std::vector<cv::Point2f> left, right;
    cv::undistortPoints(pair.left_corners, left, c.M1, c.D1, cv::noArray(), c.M1);
    cv::undistortPoints(pair.right_corners, right, c.M2, c.D2, cv::noArray(), c.M2);
    for (size_t i = 0; i < left.size(); ++i) {
      const cv::Vec3d pl(left[i].x, left[i].y, 1.0), pr(right[i].x, right[i].y, 1.0);
      const cv::Vec3d line_r = F * pl;                     // epipolar line of p_l in the right image
      const cv::Vec3d line_l = F.t() * pr;                 // epipolar line of p_r in the left image
      const double constraint = std::abs(pr.dot(line_r));  // |p_r^T F p_l|
      distance_sum +=
          0.5 * (constraint / std::hypot(line_r[0], line_r[1]) + constraint / std::hypot(line_l[0], line_l[1]));
      algebraic_sum += constraint;
      ++n;
    }
  }
  result.corner_count = n;
  result.epipolar_error_px = n ? distance_sum / n : 0.0;
  result.epipolar_algebraic = n ? algebraic_sum / n : 0.0;
}

cv::Mat FirstFive(const cv::Mat& d) {
  cv::Mat row = cv::Mat::zeros(1, 5, CV_64F);
  cv::Mat flat = d.reshape(1, 1);
  for (int i = 0; i < std::min(5, flat.cols); ++i) row.at<double>(0, i) = flat.at<double>(0, i);
  return row;
}

/// IdealComparison::left_ray_error_max_px: every 4th pixel (and the last row
/// and column) undistorted with both calibrations, the largest distance in
/// the ideal's pixels.
double RayErrorMaxPx(const cv::Mat& m, const cv::Mat& d, const cv::Mat& m_ideal, const cv::Mat& d_ideal,
                     cv::Size size) {
  std::vector<cv::Point2d> pixels;
  for (int v = 0; v < size.height; v += 4) {
    for (int u = 0; u < size.width; u += 4) pixels.emplace_back(u, v);
    pixels.emplace_back(size.width - 1, v);
  }
  for (int u = 0; u < size.width; u += 4) pixels.emplace_back(u, size.height - 1);
  std::vector<cv::Point2d> estimated, ideal;
  const cv::TermCriteria precise(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 100, 1e-14);
  cv::undistortPoints(pixels, estimated, m, d, cv::noArray(), m_ideal, precise);
  cv::undistortPoints(pixels, ideal, m_ideal, d_ideal, cv::noArray(), m_ideal, precise);
  double worst = 0.0;
  for (size_t i = 0; i < pixels.size(); ++i) worst = std::max(worst, cv::norm(estimated[i] - ideal[i]));
  return worst;
}

/// Rotation angle of a 3x3 rotation matrix [deg].
double RotationAngleDeg(const cv::Mat& r) {
  const double c = (cv::trace(r)[0] - 1.0) / 2.0;
  return std::acos(std::clamp(c, -1.0, 1.0)) * 180.0 / CV_PI;
}

// The nearest and farthest depth of the board's centre over the views of a
// calibrateCamera run (its per-view rotation and translation vectors).
void BoardDepthRange(const BoardSpec& board, const cv::Mat& rvecs, const cv::Mat& tvecs, CalibrationResult& result) {
  const cv::Vec3d centre(0.5 * (board.inner_corners_x - 1) * board.square_m,
                         0.5 * (board.inner_corners_y - 1) * board.square_m, 0.0);
  double nearest = std::numeric_limits<double>::infinity(), farthest = 0.0;
  for (int i = 0; i < static_cast<int>(rvecs.total()); ++i) {
    cv::Matx33d rotation;
    cv::Rodrigues(rvecs.at<cv::Vec3d>(i), rotation);
    const double depth = (rotation * centre + tvecs.at<cv::Vec3d>(i))[2];
    nearest = std::min(nearest, depth);
    farthest = std::max(farthest, depth);
  }
  result.board_depth_min_m = nearest;
  result.board_depth_max_m = farthest;
}

// A board image, checked against its sidecar's and the manifest's SHA-256 first.
// A thermal rig's (lwir) is windowed into 8 bits (WindowThermalImage).
cv::Mat ReadImage(const OpenedDataset& dataset, const FileRef& ref) {
  if (!dataset.has_rig() || !dataset.rig().lwir) {
    return ReadListedImage(dataset, ref, cv::IMREAD_COLOR, "calibration image");
  }
  cv::Mat image = ReadListedImage(dataset, ref, cv::IMREAD_UNCHANGED, "calibration image");
  WindowThermalImage(image, dataset.PathOf(ref.path));
  return image;
}

// The comparison's ideal: calibration_ideal.yaml where the dataset has it,
// else the rig's exact rectified calibration where it has one.
std::optional<StereoCalibration> IdealOf(const OpenedDataset& dataset) {
  if (const std::optional<std::string> yaml = dataset.ReadIfPresent(kIdealCalibrationName)) {
    return ParseCalibration(*yaml, dataset.PathOf(kIdealCalibrationName));
  }
  if (!dataset.has_rig()) return std::nullopt;
  try {
    return IdealCalibration(dataset.rig());
  } catch (const Error&) {
    return std::nullopt;  // a rig without an exact rectified ideal: no comparison
  }
}

}  // namespace

DistortionModel ParseDistortionModel(const std::string& text) {
  for (DistortionModel m : {DistortionModel::kAuto, DistortionModel::kPinhole, DistortionModel::kBrownConrady,
                            DistortionModel::kBrownConradyK3}) {
    if (text == DistortionModelName(m)) return m;
  }
  throw Error("--distortion '" + text + "': expected auto, pinhole, brown-conrady or brown-conrady-k3");
}

const char* DistortionModelName(DistortionModel model) {
  switch (model) {
    case DistortionModel::kAuto:
      return "auto";
    case DistortionModel::kPinhole:
      return "pinhole";
    case DistortionModel::kBrownConrady:
      return "brown-conrady";
    case DistortionModel::kBrownConradyK3:
      return "brown-conrady-k3";
  }
  return "?";
}

void CalibrationOptions::Check() const {
  const auto fail = [](const std::string& message) { throw Error("calibration options: " + message); };
  if (board.inner_corners_x < 2 || board.inner_corners_y < 2) fail("board needs at least 2x2 inner corners");
  if (!(board.square_m > 0)) fail("board square size must be positive");
  if (subpix_half_window_px < 1) fail("subpix_half_window_px must be at least 1");
  if (subpix_max_iterations < 1 || max_iterations < 1) fail("iteration counts must be positive");
  if (!(subpix_epsilon_px >= 0) || !(epsilon >= 0)) fail("epsilons must be non-negative");
  if (!(rectify_alpha == -1.0 || (rectify_alpha >= 0 && rectify_alpha <= 1)))
    fail("rectify_alpha must be -1 or in [0, 1]");
  if (min_pairs < 3) fail("min_pairs must be at least 3 (Zhang's method)");
  if (!(min_pair_fraction >= 0 && min_pair_fraction <= 1)) fail("min_pair_fraction must be in [0, 1]");
}

std::optional<std::vector<cv::Point2f>> DetectBoardCorners(const cv::Mat& image, const CalibrationOptions& options) {
  const cv::Mat gray = ToGrayscale(image, "board image");
  int flags = 0;
  if (options.adaptive_threshold) flags |= cv::CALIB_CB_ADAPTIVE_THRESH;
  if (options.normalize_image) flags |= cv::CALIB_CB_NORMALIZE_IMAGE;
  if (options.fast_check) flags |= cv::CALIB_CB_FAST_CHECK;
  std::vector<cv::Point2f> corners;
  const cv::Size pattern(options.board.inner_corners_x, options.board.inner_corners_y);
  if (!cv::findChessboardCorners(gray, pattern, corners, flags)) return std::nullopt;
  if (corners.size() != static_cast<size_t>(pattern.area())) return std::nullopt;
  const int w = options.subpix_half_window_px;
  cv::cornerSubPix(gray, corners, cv::Size(w, w), cv::Size(-1, -1),
                   cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, options.subpix_max_iterations,
                                    options.subpix_epsilon_px));
  return corners;
}

PairDetection DetectBoardPair(const StereoImagePair& pair, const CalibrationOptions& options) {
  PairDetection d;
  d.left_name = pair.left_name;
  d.right_name = pair.right_name;
  const std::string missing = ": found no " + BoardName(options.board) + " chessboard";
  auto left = DetectBoardCorners(ToGrayscale(pair.left, pair.left_name), options);
  if (!left) {
    d.reason = pair.left_name + missing;
    return d;
  }
  auto right = DetectBoardCorners(ToGrayscale(pair.right, pair.right_name), options);
  if (!right) {
    d.reason = pair.right_name + missing;
    return d;
  }
  const int nx = options.board.inner_corners_x, ny = options.board.inner_corners_y;
  MakeRightHanded(*left, nx, ny);
  MakeRightHanded(*right, nx, ny);
  // 180-degree ambiguity: left by the top-left-most rule, right by agreement with left.
  if (left->front().x + left->front().y > left->back().x + left->back().y) std::reverse(left->begin(), left->end());
  std::vector<cv::Point2f> reversed(right->rbegin(), right->rend());
  if (SumSquaredDistance(reversed, *left) < SumSquaredDistance(*right, *left)) right->swap(reversed);
  d.used = true;
  d.left_corners = std::move(*left);
  d.right_corners = std::move(*right);
  return d;
}

CalibrationResult CalibrateFromDetections(std::vector<PairDetection> pairs, cv::Size image_size,
                                          const CalibrationOptions& options,
                                          const std::optional<StereoCalibration>& ideal, const std::string& source) {
  options.Check();
  CalibrationResult result;
  std::vector<std::vector<cv::Point3f>> object_points;
  std::vector<std::vector<cv::Point2f>> left_points, right_points;
  const std::vector<cv::Point3f> board = BoardObjectPoints(options.board);
  for (const PairDetection& p : pairs) {
    if (!p.used) continue;
    if (p.left_corners.size() != board.size() || p.right_corners.size() != board.size()) {
      throw Error(p.left_name + ": corner count does not match the " + BoardName(options.board) + " board");
    }
    object_points.push_back(board);
    left_points.push_back(p.left_corners);
    right_points.push_back(p.right_corners);
  }
  const size_t used = object_points.size();
  const size_t needed =
      std::max(options.min_pairs, static_cast<size_t>(std::ceil(options.min_pair_fraction * pairs.size() - 1e-9)));
  if (used < needed) {
    std::ostringstream message;
    message << source << ": found the " << BoardName(options.board) << " chessboard in both images of only " << used
            << " of " << pairs.size() << " calibration pairs (need at least " << needed << ")";
    for (const PairDetection& p : pairs) {
      if (!p.used) {
        message << "; first rejected: " << p.reason;
        break;
      }
    }
    throw Error(message.str());
  }

  // Zhang's method per camera, then the stereo refinement (thesis 3.3).
  int flags = 0;
  result.same_focal_length = options.same_focal_length;
  result.distortion_estimated =
      options.distortion == DistortionModel::kBrownConrady || options.distortion == DistortionModel::kBrownConradyK3;
  if (!result.distortion_estimated)
    flags |= cv::CALIB_FIX_K1 | cv::CALIB_FIX_K2 | cv::CALIB_FIX_K3 | cv::CALIB_ZERO_TANGENT_DIST;
  if (options.distortion == DistortionModel::kBrownConrady) flags |= cv::CALIB_FIX_K3;  // k3 stays 0
  const cv::TermCriteria criteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, options.max_iterations,
                                  options.epsilon);
  StereoCalibration& c = result.calibration;
  c.image_size = image_size;
  try {
    cv::Mat d1, d2, rvecs, tvecs;
    result.left_rms_px =
        cv::calibrateCamera(object_points, left_points, image_size, c.M1, d1, rvecs, tvecs, flags, criteria);
    BoardDepthRange(options.board, rvecs, tvecs, result);
    result.right_rms_px =
        cv::calibrateCamera(object_points, right_points, image_size, c.M2, d2, rvecs, tvecs, flags, criteria);
    c.D1 = FirstFive(d1);
    c.D2 = FirstFive(d2);
    const int stereo_flags =
        flags | (options.refine_intrinsics_in_stereo ? cv::CALIB_USE_INTRINSIC_GUESS : cv::CALIB_FIX_INTRINSIC) |
        (options.same_focal_length ? cv::CALIB_SAME_FOCAL_LENGTH : 0);
    result.rms_reprojection_px = cv::stereoCalibrate(object_points, left_points, right_points, c.M1, c.D1, c.M2, c.D2,
                                                     image_size, c.R, c.T, result.E, result.F, stereo_flags, criteria);
    c.D1 = FirstFive(c.D1);
    c.D2 = FirstFive(c.D2);
    c.T = c.T.reshape(1, 3);
    // Thesis 3.5 needs Q for the left (primary) camera; CALIB_ZERO_DISPARITY
    // gives both rectified views one principal point, so Q(3,3) = 0.
    cv::stereoRectify(c.M1, c.D1, c.M2, c.D2, image_size, c.R, c.T, c.R1, c.R2, c.P1, c.P2, c.Q,
                      cv::CALIB_ZERO_DISPARITY, options.rectify_alpha, image_size);
  } catch (const cv::Exception& e) {
    throw Error(source + ": calibration failed with " + std::to_string(used) + " pairs: " + e.err);
  }
  for (cv::Mat* m : {&c.M1, &c.M2, &c.R, &c.T, &c.R1, &c.R2, &c.P1, &c.P2, &c.Q, &result.E, &result.F}) {
    m->convertTo(*m, CV_64F);
  }

  result.used_pairs = used;
  result.pairs = std::move(pairs);
  EpipolarErrors(result.pairs, c, result.F, result);
  if (ideal) result.versus_ideal = CompareToIdeal(c, *ideal);
  return result;
}

CalibrationResult CalibrateFromImages(const std::vector<StereoImagePair>& pairs, const CalibrationOptions& options,
                                      const std::optional<StereoCalibration>& ideal) {
  if (pairs.empty()) throw Error("calibration: no image pairs given");
  const cv::Size size = pairs.front().left.size();
  std::vector<PairDetection> detections;
  for (const StereoImagePair& p : pairs) {
    if (p.left.size() != size) throw Error(p.left_name + ": image size differs from " + pairs.front().left_name);
    if (p.right.size() != size) throw Error(p.right_name + ": image size differs from " + pairs.front().left_name);
    detections.push_back(DetectBoardPair(p, options));
  }
  return CalibrateFromDetections(std::move(detections), size, options, ideal, "images");
}

CalibrationResult CalibrateFromDataset(const OpenedDataset& dataset, const CalibrationOptions& options) {
  const Manifest& manifest = dataset.manifest();
  if (manifest.calib_pair_count == 0) {
    throw Error(dataset.folder().string() + ": the manifest lists no calibration pairs");
  }
  CalibrationOptions opts = options;
  if (opts.distortion == DistortionModel::kAuto) {
    // The lens model the rig declares (a camera with "distortion"), never its coefficients.
    const bool distorted = dataset.has_rig() && HasDistortion(dataset.rig());
    opts.distortion = distorted ? DistortionModel::kBrownConrady : DistortionModel::kPinhole;
  }

  std::vector<PairDetection> detections;
  cv::Size size;
  for (size_t i = 0; i < manifest.calib_pair_count; ++i) {
    const FrameSidecar sidecar = dataset.Sidecar("calib", i);
    // The board the first sidecar records (the physical board, not truth).
    if (i == 0 && sidecar.board) opts.board = *sidecar.board;
    StereoImagePair pair;
    pair.left_name = sidecar.files.at("left").path;
    pair.right_name = sidecar.files.at("right").path;
    pair.left = ReadImage(dataset, sidecar.files.at("left"));
    pair.right = ReadImage(dataset, sidecar.files.at("right"));
    if (i == 0) size = pair.left.size();
    for (const auto& [image, name] :
         {std::pair{&pair.left, &pair.left_name}, std::pair{&pair.right, &pair.right_name}}) {
      if (image->size() != size) {
        throw Error(dataset.PathOf(*name) + ": image is " + std::to_string(image->cols) + "x" +
                    std::to_string(image->rows) + ", expected " + std::to_string(size.width) + "x" +
                    std::to_string(size.height));
      }
    }
    detections.push_back(DetectBoardPair(pair, opts));
  }
  return CalibrateFromDetections(std::move(detections), size, opts, IdealOf(dataset), dataset.folder().string());
}

cv::Mat QPercentError(const cv::Mat& q, const cv::Mat& q_ideal) {
  if (q.size() != cv::Size(4, 4) || q_ideal.size() != cv::Size(4, 4)) throw Error("QPercentError: Q must be 4x4");
  cv::Mat a, b;
  q.convertTo(a, CV_64F);
  q_ideal.convertTo(b, CV_64F);
  cv::Mat error = cv::Mat::zeros(4, 4, CV_64F);
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) {
      const double ideal = b.at<double>(r, c);
      if (ideal != 0.0) error.at<double>(r, c) = 100.0 * std::abs(a.at<double>(r, c) - ideal) / std::abs(ideal);
    }
  }
  return error;
}

IdealComparison CompareToIdeal(const StereoCalibration& estimated, const StereoCalibration& ideal) {
  auto at = [](const cv::Mat& m, int r, int c) {
    cv::Mat d;
    m.convertTo(d, CV_64F);
    return d.at<double>(r, c);
  };
  auto percent = [](double value, double truth) { return 100.0 * (value - truth) / truth; };
  IdealComparison cmp;
  cmp.q_percent_error = QPercentError(estimated.Q, ideal.Q);
  cmp.focal_error_percent = percent(at(estimated.Q, 2, 3), at(ideal.Q, 2, 3));
  cmp.baseline_error_percent = percent(cv::norm(estimated.T), cv::norm(ideal.T));
  cmp.left_fx_error_percent = percent(at(estimated.M1, 0, 0), at(ideal.M1, 0, 0));
  cmp.right_fx_error_percent = percent(at(estimated.M2, 0, 0), at(ideal.M2, 0, 0));
  cmp.left_principal_point_error_px =
      std::hypot(at(estimated.M1, 0, 2) - at(ideal.M1, 0, 2), at(estimated.M1, 1, 2) - at(ideal.M1, 1, 2));
  cmp.rectified_principal_point_error_px =
      std::hypot(at(estimated.Q, 0, 3) - at(ideal.Q, 0, 3), at(estimated.Q, 1, 3) - at(ideal.Q, 1, 3));
  cv::Mat r, r_ideal, t, t_ideal, r1;
  estimated.R.convertTo(r, CV_64F);
  ideal.R.convertTo(r_ideal, CV_64F);
  estimated.T.convertTo(t, CV_64F);
  ideal.T.convertTo(t_ideal, CV_64F);
  estimated.R1.convertTo(r1, CV_64F);
  cmp.rotation_error_deg = RotationAngleDeg(r * r_ideal.t());
  cmp.baseline_direction_error_deg =
      std::acos(std::clamp(t.dot(t_ideal) / (cv::norm(t) * cv::norm(t_ideal)), -1.0, 1.0)) * 180.0 / CV_PI;
  cmp.rectification_angle_deg = RotationAngleDeg(r1);
  for (int i = 0; i < 5; ++i) {
    cmp.left_distortion_error[i] = at(estimated.D1, 0, i) - at(ideal.D1, 0, i);
    cmp.right_distortion_error[i] = at(estimated.D2, 0, i) - at(ideal.D2, 0, i);
  }
  cmp.left_ray_error_max_px = RayErrorMaxPx(estimated.M1, estimated.D1, ideal.M1, ideal.D1, ideal.image_size);
  cmp.right_ray_error_max_px = RayErrorMaxPx(estimated.M2, estimated.D2, ideal.M2, ideal.D2, ideal.image_size);
  return cmp;
}

std::string CalibrationResult::BriefReport() const {
  std::ostringstream out;
  out << "calibration: " << used_pairs << " of " << pairs.size() << " pairs used, " << corner_count
      << " corners per image\n";
  for (const PairDetection& p : pairs) {
    if (!p.used) out << "  rejected: " << p.reason << "\n";
  }
  out << "  RMS re-projection " << FormatFixed(rms_reprojection_px, 6) << " px (left " << FormatFixed(left_rms_px, 6)
      << ", right " << FormatFixed(right_rms_px, 6) << "), epipolar " << FormatFixed(epipolar_error_px, 6) << " px\n";
  const auto coefficients = [](const cv::Mat& d) {
    std::string text;
    for (int i = 0; i < 5; ++i) text += (i ? " " : "") + FormatFixed(d.at<double>(0, i), 6);
    return text;
  };
  if (distortion_estimated) {
    out << "  distortion k1 k2 p1 p2 k3: left " << coefficients(calibration.D1) << ", right "
        << coefficients(calibration.D2) << "\n";
  }
  out << "  focal " << FormatFixed(calibration.Q.at<double>(2, 3), 3) << " px, baseline "
      << FormatFixed(cv::norm(calibration.T), 6) << " m (z component "
      << FormatFixed(1e3 * calibration.T.at<double>(2), 2) << " mm)"
      << (same_focal_length ? ", one focal length for both cameras" : "") << "\n";
  out << "  boards " << FormatFixed(board_depth_min_m, 1) << "-" << FormatFixed(board_depth_max_m, 1)
      << " m from the left camera";
  if (board_depth_max_m < 1.5 * board_depth_min_m && !same_focal_length) {
    out << ": at one depth the baseline's z component and the focal-length ratio are hard to tell apart (boards at "
           "other distances separate them: aar-render calib's default 36, or --far-boards; for a matched pair, "
           "aar-analyze calibrate --same-focal-length)";
  }
  out << "\n";
  if (versus_ideal) {
    out << "  versus ideal: focal " << FormatFixed(versus_ideal->focal_error_percent, 4) << " %, baseline "
        << FormatFixed(versus_ideal->baseline_error_percent, 4) << " %, left principal point "
        << FormatFixed(versus_ideal->left_principal_point_error_px, 3) << " px, rotation "
        << FormatFixed(versus_ideal->rotation_error_deg, 4) << " deg, baseline direction "
        << FormatFixed(versus_ideal->baseline_direction_error_deg, 4) << " deg\n";
    if (distortion_estimated) {
      const auto errors = [](const std::array<double, 5>& e) {
        std::string text;
        for (int i = 0; i < 5; ++i) text += (i ? " " : "") + FormatFixed(e[i], 6);
        return text;
      };
      out << "  distortion error (estimate - ideal) k1 k2 p1 p2 k3: left "
          << errors(versus_ideal->left_distortion_error) << ", right " << errors(versus_ideal->right_distortion_error)
          << "\n";
    }
    if (distortion_estimated || versus_ideal->left_ray_error_max_px > 0.0) {
      out << "  largest ray error over the image (undistorted pixel, estimate against ideal): left "
          << FormatFixed(versus_ideal->left_ray_error_max_px, 3) << " px, right "
          << FormatFixed(versus_ideal->right_ray_error_max_px, 3) << " px\n";
    }
    out << "  Q percent error:\n";
    for (int r = 0; r < 4; ++r) {
      out << "   ";
      for (int c = 0; c < 4; ++c) out << " " << FormatFixed(versus_ideal->q_percent_error.at<double>(r, c), 3) << "%";
      out << "\n";
    }
  }
  return out.str();
}

}  // namespace aar
