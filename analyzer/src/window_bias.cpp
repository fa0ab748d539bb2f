#include "aar/analyzer/window_bias.h"

#include <Eigen/Dense>
#include <cmath>
#include <limits>

#include "aar/analyzer/depth_raster.h"
#include "aar/error.h"

namespace aar {

void WindowBiasOptions::Check() const {
  if (half_window_px < 1 || half_window_px > 32) throw Error("window bias: half_window_px must be in [1, 32]");
  if (!(min_model_fraction > 0.0 && min_model_fraction <= 1.0)) {
    throw Error("window bias: min_model_fraction must be in (0, 1]");
  }
  if (!(max_bias_px > 0.0)) throw Error("window bias: max_bias_px must be positive");
}

cv::Mat ModelDisparity(const TriangleMesh& mesh, const StereoCalibration& calibration,
                       const Eigen::Isometry3d& rect_left_from_receiver, const cv::Rect& region, double near_m) {
  cv::Mat p1, q;
  calibration.P1.convertTo(p1, CV_64F);
  calibration.Q.convertTo(q, CV_64F);
  Intrinsics k;
  k.width_px = region.width;
  k.height_px = region.height;
  k.fx_px = p1.at<double>(0, 0);
  k.fy_px = p1.at<double>(1, 1);
  k.cx_px = p1.at<double>(0, 2) - region.x;
  k.cy_px = p1.at<double>(1, 2) - region.y;
  const DepthBuffer depth = RasterizeDepth(mesh, k, rect_left_from_receiver, near_m);
  const double q23 = q.at<double>(2, 3), q32 = q.at<double>(3, 2), q33 = q.at<double>(3, 3);
  cv::Mat disparity(region.size(), CV_32F);
  for (int y = 0; y < region.height; ++y) {
    float* row = disparity.ptr<float>(y);
    for (int x = 0; x < region.width; ++x) {
      const double z = depth.At(x, y);
      row[x] = std::isfinite(z) ? static_cast<float>((q23 / z - q33) / q32) : std::numeric_limits<float>::quiet_NaN();
    }
  }
  return disparity;
}

std::vector<double> PredictWindowBias(const cv::Mat& rect_left, const cv::Mat& rect_right,
                                      const cv::Mat& model_disparity, cv::Point origin,
                                      const std::vector<Eigen::Vector3d>& pixels, const WindowBiasOptions& options) {
  options.Check();
  if (rect_left.type() != CV_8UC1 || rect_right.type() != CV_8UC1 || model_disparity.type() != CV_32FC1 ||
      rect_left.size() != rect_right.size() || rect_left.size() != model_disparity.size()) {
    throw Error("window bias: images must be 8-bit grey and the model's disparity CV_32F, all of one size");
  }
  const int h = options.half_window_px;
  const int n = (2 * h + 1) * (2 * h + 1);
  const int parameters = options.slanted ? 3 : 1;
  const auto gradient = [](const cv::Mat& image, int x, int y) {
    const uint8_t* row = image.ptr<uint8_t>(y);
    return 0.5 * (static_cast<double>(row[x + 1]) - static_cast<double>(row[x - 1]));
  };
  std::vector<double> bias(pixels.size(), 0.0);
  Eigen::MatrixXd jacobian(n, parameters);
  Eigen::VectorXd target(n);
  for (size_t k = 0; k < pixels.size(); ++k) {
    const int u = static_cast<int>(std::lround(pixels[k].x())) - origin.x;
    const int v = static_cast<int>(std::lround(pixels[k].y())) - origin.y;
    const int d_int = static_cast<int>(std::lround(pixels[k].z()));
    if (v - h < 0 || v + h >= rect_left.rows || u - h - 1 < 0 || u + h + 1 >= rect_left.cols || u - d_int - h - 1 < 0 ||
        u - d_int + h + 1 >= rect_left.cols) {
      continue;
    }
    const double centre = model_disparity.at<float>(v, u);
    if (!std::isfinite(centre)) continue;
    int on_model = 0, row = 0;
    for (int i = -h; i <= h; ++i) {
      for (int j = -h; j <= h; ++j, ++row) {
        const double d = model_disparity.at<float>(v + i, u + j);
        // Off the model: no weight (its disparity is unknown).
        const double g = std::isfinite(d)
                             ? 0.5 * (gradient(rect_left, u + j, v + i) + gradient(rect_right, u + j - d_int, v + i))
                             : 0.0;
        on_model += std::isfinite(d) ? 1 : 0;
        jacobian(row, 0) = g;
        if (options.slanted) {
          jacobian(row, 1) = g * j;
          jacobian(row, 2) = g * i;
        }
        target(row) = std::isfinite(d) ? g * d : 0.0;
      }
    }
    if (on_model < options.min_model_fraction * n) continue;
    // The refinement's zero-mean normal equations (its brightness offset),
    // over the samples on the model.
    Eigen::RowVectorXd mean = jacobian.colwise().sum() / on_model;
    Eigen::MatrixXd centred = jacobian;
    row = 0;
    for (int i = -h; i <= h; ++i) {
      for (int j = -h; j <= h; ++j, ++row) {
        if (std::isfinite(model_disparity.at<float>(v + i, u + j))) centred.row(row) -= mean;
      }
    }
    const Eigen::MatrixXd normal = centred.transpose() * centred;
    const Eigen::VectorXd fit = normal.ldlt().solve(centred.transpose() * target);
    if (!fit.allFinite()) continue;
    const double predicted = fit(0) - centre;
    if (std::abs(predicted) <= options.max_bias_px) bias[k] = predicted;
  }
  return bias;
}

}  // namespace aar
