#include "aar/analyzer/reprojection.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/core/eigen.hpp>
#include <vector>

#include "aar/error.h"

namespace aar {

namespace {

// Eq. 1's depth (z in rect_left) of each value of a disparity map. A
// rectifying Q (cv::stereoRectify's) has no u or v in its last two rows, so
// z = (Q22 d + Q23) / (Q32 d + Q33) depends on the disparity alone and is
// tabulated once over the values the map holds: the same double operations
// as the 4x4 product, whose u and v terms are exact zeros there. Any other Q
// is evaluated per pixel. NaN marks a point that is not finite.
class DepthOfDisparity {
 public:
  DepthOfDisparity(const Eigen::Matrix4d& q, const cv::Mat& disparity16, int invalid_value16,
                   const ReprojectionOptions& options)
      : q_(q), matcher_bias_px_(options.matcher_bias_px), offset_px_(options.disparity_offset_px) {
    const bool rectifying = q.allFinite() && q(2, 0) == 0.0 && q(2, 1) == 0.0 && q(3, 0) == 0.0 && q(3, 1) == 0.0;
    double max_value = 0.0;
    cv::minMaxLoc(disparity16, nullptr, &max_value);
    if (!rectifying || !(max_value > invalid_value16)) return;
    first_ = invalid_value16 + 1;
    table_.resize(static_cast<size_t>(static_cast<int>(max_value) - first_ + 1));
    for (size_t k = 0; k < table_.size(); ++k) {
      const double d = Disparity(static_cast<short>(first_ + static_cast<int>(k)));
      const double z = (q(2, 2) * d + q(2, 3)) / (q(3, 2) * d + q(3, 3));
      table_[k] = std::isfinite(z) && q(3, 2) * d + q(3, 3) != 0.0 ? z : std::numeric_limits<double>::quiet_NaN();
    }
  }

  /// The disparity eq. 1 uses for a map value [px].
  double Disparity(short value16) const { return value16 / 16.0 - matcher_bias_px_ - offset_px_; }

  /// Eq. 1's point in rect_left at pixel (u, v) with disparity d [m].
  Eigen::Vector3d Point(double u, double v, double d) const {
    const Eigen::Vector4d h = q_ * Eigen::Vector4d(u, v, d, 1.0);
    return h.head<3>() / h.w();
  }

  /// z of pixel (u, v) holding a valid `value16`, NaN when its point is not finite [m].
  double Depth(int u, int v, short value16) const {
    if (!table_.empty()) return table_[static_cast<size_t>(value16 - first_)];
    const Eigen::Vector3d p = Point(u, v, Disparity(value16));
    return p.allFinite() ? p.z() : std::numeric_limits<double>::quiet_NaN();
  }

 private:
  Eigen::Matrix4d q_;
  double matcher_bias_px_, offset_px_;
  int first_ = 0;
  std::vector<double> table_;  // empty: evaluated per pixel
};

// The decimation step: keep_one_in, or the target_points step over the
// points in the depth gate; narrows max_z to the median gate.
size_t DecimationStep(const cv::Mat& disparity16, int invalid_value16, const DepthOfDisparity& depth,
                      const ReprojectionOptions& options, cv::Point origin, double& max_z) {
  if (options.target_points == 0 && !(options.max_depth_over_median > 0.0)) return options.keep_one_in;
  // Depths of the points that pass the depth filter: for the median gate and
  // the target_points step (which counts only these: a textured background
  // kilometres away has valid disparities too, and counting them would thin
  // the receiver's cloud out).
  std::vector<double> depths;
  for (int row_index = 0; row_index < disparity16.rows; ++row_index) {
    const short* row = disparity16.ptr<short>(row_index);
    for (int column = 0; column < disparity16.cols; ++column) {
      if (row[column] <= invalid_value16) continue;
      const double z = depth.Depth(column + origin.x, row_index + origin.y, row[column]);
      if (z > options.min_depth_m && !(z > max_z)) depths.push_back(z);
    }
  }
  size_t in_gate = depths.size();
  if (options.max_depth_over_median > 0.0 && !depths.empty()) {
    // In place: only the count below uses `depths` afterwards, and it ignores order.
    const auto middle = depths.begin() + static_cast<std::ptrdiff_t>(depths.size() / 2);
    std::nth_element(depths.begin(), middle, depths.end());
    max_z = std::min(max_z, options.max_depth_over_median * *middle);
    in_gate = static_cast<size_t>(std::count_if(depths.begin(), depths.end(), [&](double z) { return !(z > max_z); }));
  }
  return options.target_points > 0 ? std::max(options.keep_one_in, in_gate / options.target_points)
                                   : options.keep_one_in;
}

}  // namespace

SensedCloud Reproject(const cv::Mat& disparity16, int invalid_value16, const StereoCalibration& calibration,
                      const Eigen::Isometry3d& tanker_from_left, const ReprojectionOptions& options,
                      const SubpixelRefiner* refiner, cv::Point origin) {
  if (disparity16.type() != CV_16SC1) throw Error("re-projection: disparity must be CV_16S (disparity * 16)");
  if (calibration.Q.rows != 4 || calibration.Q.cols != 4 || calibration.R1.rows != 3 || calibration.R1.cols != 3) {
    throw Error("re-projection: calibration needs a 4x4 Q and a 3x3 R1");
  }
  if (options.keep_one_in == 0) throw Error("re-projection: keep_one_in must be at least 1");

  Eigen::Matrix4d q;
  Eigen::Matrix3d r1;
  cv::Mat q64, r64;
  calibration.Q.convertTo(q64, CV_64F);
  calibration.R1.convertTo(r64, CV_64F);
  cv::cv2eigen(q64, q);
  cv::cv2eigen(r64, r1);
  // point_in_tanker = tanker_from_left * R1^T * point_in_rect_left (thesis eqs. 2-3).
  Eigen::Isometry3d left_from_rect_left = Eigen::Isometry3d::Identity();
  left_from_rect_left.linear() = r1.transpose();
  const Eigen::Isometry3d tanker_from_rect_left = tanker_from_left * left_from_rect_left;

  const DepthOfDisparity depth(q, disparity16, invalid_value16, options);
  const double min_z = options.min_depth_m;
  double max_z = options.max_depth_m;
  const size_t step = DecimationStep(disparity16, invalid_value16, depth, options, origin, max_z);
  const auto in_range = [&](const Eigen::Vector3d& p) { return p.allFinite() && p.z() > min_z && !(p.z() > max_z); };

  SensedCloud cloud;
  for (int row_index = 0; row_index < disparity16.rows; ++row_index) {
    const short* row = disparity16.ptr<short>(row_index);
    const int v = row_index + origin.y;
    for (int column = 0; column < disparity16.cols; ++column) {
      if (row[column] <= invalid_value16) continue;
      const int u = column + origin.x;
      const double z = depth.Depth(u, v, row[column]);
      if (!(z > min_z && !(z > max_z))) continue;
      if (cloud.valid_count++ % step != 0) continue;
      const double matched = row[column] / 16.0 - options.matcher_bias_px;
      const double d = matched - options.disparity_offset_px;
      Eigen::Vector3d point_in_rect_left = depth.Point(u, v, d);
      Eigen::Vector3d pixel(u, v, d);
      if (refiner != nullptr) {
        const auto refined = refiner->Refine(u, v, matched);
        if (!refined) {
          ++cloud.refine_rejected;
          continue;
        }
        pixel = Eigen::Vector3d(refined->u_px, v, refined->disparity_px - options.disparity_offset_px);
        point_in_rect_left = depth.Point(pixel.x(), v, pixel.z());
        if (!in_range(point_in_rect_left)) continue;
      }
      cloud.points_in_tanker.push_back(tanker_from_rect_left * point_in_rect_left);
      cloud.pixels.push_back(pixel);
    }
  }
  cloud.kept_count = cloud.points_in_tanker.size();
  return cloud;
}

}  // namespace aar
