#include "aar/stereo_calibration.h"

#include <cmath>
#include <opencv2/core/eigen.hpp>

#include "aar/error.h"
#include "aar/file_io.h"

namespace aar {

StereoCalibration IdealCalibration(const StereoRig& rig) {
  const Intrinsics& kl = rig.left.intrinsics;
  const Intrinsics& kr = rig.right.intrinsics;
  const Eigen::Isometry3d right_from_left = rig.RightFromLeft();
  const Eigen::Vector3d t = right_from_left.translation();
  const bool parallel = (right_from_left.linear() - Eigen::Matrix3d::Identity()).norm() < 1e-9 &&
                        std::abs(t.y()) < 1e-9 && std::abs(t.z()) < 1e-9 && t.x() < 0;
  const bool same = kl.fx_px == kr.fx_px && kl.fy_px == kr.fy_px && kl.cx_px == kr.cx_px && kl.cy_px == kr.cy_px &&
                    kl.width_px == kr.width_px && kl.height_px == kr.height_px && kl.fx_px == kl.fy_px;
  if (!parallel || !same) {
    throw Error(
        "ideal calibration needs parallel cameras with identical square-pixel intrinsics, offset along the left "
        "camera's +x");
  }
  const double b = -t.x();
  StereoCalibration c;
  c.image_size = cv::Size(kl.width_px, kl.height_px);
  cv::eigen2cv(Eigen::Matrix3d(kl.CameraMatrix()), c.M1);
  cv::eigen2cv(Eigen::Matrix3d(kr.CameraMatrix()), c.M2);
  c.D1 = cv::Mat::zeros(1, 5, CV_64F);
  c.D2 = cv::Mat::zeros(1, 5, CV_64F);
  c.R = cv::Mat::eye(3, 3, CV_64F);
  c.T = (cv::Mat_<double>(3, 1) << t.x(), 0.0, 0.0);
  c.R1 = cv::Mat::eye(3, 3, CV_64F);
  c.R2 = cv::Mat::eye(3, 3, CV_64F);
  const double f = kl.fx_px;
  c.P1 = (cv::Mat_<double>(3, 4) << f, 0, kl.cx_px, 0, 0, f, kl.cy_px, 0, 0, 0, 1, 0);
  c.P2 = (cv::Mat_<double>(3, 4) << f, 0, kl.cx_px, -f * b, 0, f, kl.cy_px, 0, 0, 0, 1, 0);
  c.Q = (cv::Mat_<double>(4, 4) << 1, 0, 0, -kl.cx_px, 0, 1, 0, -kl.cy_px, 0, 0, 0, f, 0, 0, 1.0 / b, 0);
  return c;
}

std::string CalibrationToYaml(const StereoCalibration& c) {
  cv::FileStorage fs(".yaml", cv::FileStorage::WRITE | cv::FileStorage::MEMORY | cv::FileStorage::FORMAT_YAML);
  fs << "image_size" << c.image_size;
  fs << "M1" << c.M1 << "D1" << c.D1 << "M2" << c.M2 << "D2" << c.D2;
  fs << "R" << c.R << "T" << c.T << "R1" << c.R1 << "R2" << c.R2 << "P1" << c.P1 << "P2" << c.P2 << "Q" << c.Q;
  return fs.releaseAndGetString();
}

void WriteCalibration(const std::filesystem::path& path, const StereoCalibration& calibration) {
  WriteFileAtomic(path, CalibrationToYaml(calibration));
}

StereoCalibration ReadCalibration(const std::filesystem::path& path) {
  if (!std::filesystem::is_regular_file(path)) throw Error(path.string() + ": calibration file not found");
  cv::FileStorage fs;
  try {
    if (!fs.open(path.string(), cv::FileStorage::READ)) throw Error(path.string() + ": cannot parse calibration file");
  } catch (const cv::Exception& e) {
    throw Error(path.string() + ": cannot parse calibration file (" + e.err + ")");
  }
  StereoCalibration c;
  auto read = [&](const char* name, int rows, int cols) {
    cv::Mat m;
    fs[name] >> m;
    if (m.empty()) throw Error(path.string() + ": missing node " + name);
    if (m.rows != rows || m.cols != cols) {
      throw Error(path.string() + ": node " + name + " is " + std::to_string(m.rows) + "x" + std::to_string(m.cols) +
                  ", expected " + std::to_string(rows) + "x" + std::to_string(cols));
    }
    m.convertTo(m, CV_64F);
    if (!cv::checkRange(m)) throw Error(path.string() + ": node " + std::string(name) + " has non-finite values");
    return m;
  };
  fs["image_size"] >> c.image_size;
  if (c.image_size.width <= 0 || c.image_size.height <= 0) throw Error(path.string() + ": missing or bad image_size");
  c.M1 = read("M1", 3, 3);
  c.D1 = read("D1", 1, 5);
  c.M2 = read("M2", 3, 3);
  c.D2 = read("D2", 1, 5);
  c.R = read("R", 3, 3);
  c.T = read("T", 3, 1);
  c.R1 = read("R1", 3, 3);
  c.R2 = read("R2", 3, 3);
  c.P1 = read("P1", 3, 4);
  c.P2 = read("P2", 3, 4);
  c.Q = read("Q", 4, 4);
  return c;
}

}  // namespace aar
