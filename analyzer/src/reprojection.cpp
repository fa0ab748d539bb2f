#include "aar/analyzer/reprojection.h"

#include <algorithm>
#include <cmath>
#include <opencv2/core/eigen.hpp>

#include "aar/error.h"

namespace aar {

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

  const auto point_at = [&](int u, int v, double d) {
    const Eigen::Vector4d h = q * Eigen::Vector4d(u, v, d, 1.0);  // thesis eq. 1
    return Eigen::Vector3d(h.head<3>() / h.w());
  };
  const double min_z = options.min_depth_m;
  double max_z = options.max_depth_m;
  const auto in_range = [&](const Eigen::Vector3d& p) { return p.allFinite() && p.z() > min_z && !(p.z() > max_z); };

  // Depths of the points that pass the depth filter: for the median gate and
  // the target_points step (which counts only these: a textured background
  // kilometres away has valid disparities too, and counting them would thin
  // the receiver's cloud out).
  std::vector<double> depths;
  if (options.target_points > 0 || options.max_depth_over_median > 0.0) {
    for (int row_index = 0; row_index < disparity16.rows; ++row_index) {
      const short* row = disparity16.ptr<short>(row_index);
      for (int column = 0; column < disparity16.cols; ++column) {
        if (row[column] <= invalid_value16) continue;
        const double d = row[column] / 16.0 - options.matcher_bias_px - options.disparity_offset_px;
        const Eigen::Vector3d p = point_at(column + origin.x, row_index + origin.y, d);
        if (in_range(p)) depths.push_back(p.z());
      }
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
  size_t step = options.keep_one_in;
  if (options.target_points > 0) step = std::max(step, in_gate / options.target_points);

  SensedCloud cloud;
  for (int row_index = 0; row_index < disparity16.rows; ++row_index) {
    const short* row = disparity16.ptr<short>(row_index);
    const int v = row_index + origin.y;
    for (int column = 0; column < disparity16.cols; ++column) {
      if (row[column] <= invalid_value16) continue;
      const int u = column + origin.x;
      const double matched = row[column] / 16.0 - options.matcher_bias_px;
      const double d = matched - options.disparity_offset_px;
      Eigen::Vector3d point_in_rect_left = point_at(u, v, d);
      if (!in_range(point_in_rect_left)) continue;
      if (cloud.valid_count++ % step != 0) continue;
      Eigen::Vector3d pixel(u, v, d);
      if (refiner != nullptr) {
        const auto refined = refiner->Refine(u, v, matched);
        if (!refined) {
          ++cloud.refine_rejected;
          continue;
        }
        pixel = Eigen::Vector3d(refined->u_px, v, refined->disparity_px - options.disparity_offset_px);
        const Eigen::Vector4d r = q * Eigen::Vector4d(pixel.x(), v, pixel.z(), 1.0);
        point_in_rect_left = r.head<3>() / r.w();
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
