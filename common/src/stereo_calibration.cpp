#include "aar/stereo_calibration.h"

#include <array>
#include <cmath>
#include <opencv2/core/eigen.hpp>

#include "aar/calibration_yaml.h"
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
  const auto distortion = [](const BrownConrady& d) {
    const std::array<double, 5> k = d.OpenCvOrder();
    cv::Mat row(1, 5, CV_64F);
    for (int i = 0; i < 5; ++i) row.at<double>(0, i) = k[static_cast<size_t>(i)];
    return row;
  };
  c.D1 = distortion(kl.distortion);
  c.D2 = distortion(kr.distortion);
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

void CheckCalibration(const StereoCalibration& c, const std::string& where) {
  const auto positive = [&](const cv::Mat& m, int r, int col, const char* what) {
    if (!(m.at<double>(r, col) > 0.0)) throw Error(where + ": " + what + " must be positive");
  };
  positive(c.M1, 0, 0, "M1 fx");
  positive(c.M1, 1, 1, "M1 fy");
  positive(c.M2, 0, 0, "M2 fx");
  positive(c.M2, 1, 1, "M2 fy");
  positive(c.P1, 0, 0, "P1 fx");
  // Q = [[1,0,0,-cx],[0,1,0,-cy],[0,0,0,f],[0,0,1/b,0]] up to sign: re-projection needs f and 1/b.
  if (c.Q.at<double>(2, 3) == 0.0 || c.Q.at<double>(3, 2) == 0.0) {
    throw Error(where + ": Q has no focal length Q(2,3) or inverse baseline Q(3,2) (all-zero or degenerate Q)");
  }
}

StereoCalibration ReadCalibration(const std::filesystem::path& path) {
  const std::string where = path.string();
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw Error(where + ": calibration file not found");
  if (std::filesystem::file_size(path, ec) > kMaxCalibrationYamlBytes) {
    throw Error(where + ": larger than a calibration file can be (" + std::to_string(kMaxCalibrationYamlBytes) +
                " bytes)");
  }
  return ParseCalibration(ReadFileBytes(path), where);
}

StereoCalibration ParseCalibration(const std::string& text, const std::string& where) {
  if (text.size() > kMaxCalibrationYamlBytes) {
    throw Error(where + ": larger than a calibration file can be (" + std::to_string(kMaxCalibrationYamlBytes) +
                " bytes)");
  }
  std::map<std::string, cv::Mat> nodes;
  try {
    nodes = ParseOpenCvYaml(text, where);
  } catch (const Error& e) {
    throw Error(std::string(e.what()) + " (cannot parse calibration file)");
  }
  auto read = [&](const char* name, int rows, int cols) {
    const auto it = nodes.find(name);
    if (it == nodes.end() || it->second.empty()) throw Error(where + ": missing node " + name);
    const cv::Mat& m = it->second;
    if (m.rows != rows || m.cols != cols) {
      throw Error(where + ": node " + name + " is " + std::to_string(m.rows) + "x" + std::to_string(m.cols) +
                  ", expected " + std::to_string(rows) + "x" + std::to_string(cols));
    }
    if (!cv::checkRange(m)) throw Error(where + ": node " + std::string(name) + " has non-finite values");
    return m.clone();
  };
  StereoCalibration c;
  const auto size = nodes.find("image_size");
  if (size == nodes.end() || size->second.rows != 1 || size->second.cols != 2) {
    throw Error(where + ": missing or bad image_size (expected [ width, height ])");
  }
  const double width = size->second.at<double>(0, 0);
  const double height = size->second.at<double>(0, 1);
  if (!(width >= 1 && width <= 16384 && height >= 1 && height <= 16384) || width != std::floor(width) ||
      height != std::floor(height)) {
    throw Error(where + ": image_size must be two integers from 1 to 16384");
  }
  c.image_size = cv::Size(static_cast<int>(width), static_cast<int>(height));
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
  CheckCalibration(c, where);
  return c;
}

}  // namespace aar
