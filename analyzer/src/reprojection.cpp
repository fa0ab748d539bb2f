#include "aar/analyzer/reprojection.h"

#include <cmath>

#include <opencv2/core/eigen.hpp>

#include "aar/error.h"

namespace aar {

SensedCloud Reproject(const cv::Mat& disparity16, int invalid_value16, const StereoCalibration& calibration,
                      const Eigen::Isometry3d& tanker_from_left, const ReprojectionOptions& options) {
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

  SensedCloud cloud;
  const double min_z = options.min_depth_m, max_z = options.max_depth_m;
  for (int v = 0; v < disparity16.rows; ++v) {
    const short* row = disparity16.ptr<short>(v);
    for (int u = 0; u < disparity16.cols; ++u) {
      if (row[u] <= invalid_value16) continue;
      const double d = row[u] / 16.0 - options.disparity_offset_px;
      const Eigen::Vector4d h = q * Eigen::Vector4d(u, v, d, 1.0);  // thesis eq. 1
      const Eigen::Vector3d point_in_rect_left = h.head<3>() / h.w();
      const double z = point_in_rect_left.z();
      if (!point_in_rect_left.allFinite() || !(z > min_z) || z > max_z) continue;
      if (cloud.valid_count++ % options.keep_one_in == 0) {
        cloud.points_in_tanker.push_back(tanker_from_rect_left * point_in_rect_left);
      }
    }
  }
  cloud.kept_count = cloud.points_in_tanker.size();
  return cloud;
}

}  // namespace aar
