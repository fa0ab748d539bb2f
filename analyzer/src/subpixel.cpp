#include "aar/analyzer/subpixel.h"

#include <Eigen/Dense>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "aar/error.h"

namespace aar {
namespace {

// Linear interpolation along a row at column x (0 <= x < cols - 1; x is not
// negative, so truncation is the floor, without a call to floor()).
inline float SampleRow(const float* row, double x) {
  const int x0 = static_cast<int>(x);
  const float a = static_cast<float>(x - x0);
  return row[x0] + a * (row[x0 + 1] - row[x0]);
}

}  // namespace

void SubpixelOptions::Check() const {
  if (half_window_px < 1 || half_window_px > 32) throw Error("sub-pixel: half_window_px must be in [1, 32]");
  if (max_iterations < 1) throw Error("sub-pixel: max_iterations must be >= 1");
  if (!(tolerance_px > 0.0)) throw Error("sub-pixel: tolerance_px must be positive");
  if (!(max_correction_px > 0.0)) throw Error("sub-pixel: max_correction_px must be positive");
  if (!(min_gradient_energy >= 0.0)) throw Error("sub-pixel: min_gradient_energy must be >= 0");
  if (!(max_slope > 0.0 && max_slope <= 1.0)) throw Error("sub-pixel: max_slope must be in (0, 1]");
}

SubpixelRefiner::SubpixelRefiner(const cv::Mat& rect_left_gray, const cv::Mat& rect_right_gray,
                                 const SubpixelOptions& options, cv::Point origin)
    : options_(options), origin_(origin) {
  options_.Check();
  if (rect_left_gray.type() != CV_8UC1 || rect_right_gray.type() != CV_8UC1 ||
      rect_left_gray.size() != rect_right_gray.size()) {
    throw Error("sub-pixel: rectified images must be 8-bit grayscale of one size");
  }
  rect_left_gray.convertTo(left_, CV_32F);
  rect_right_gray.convertTo(right_, CV_32F);
  // Central differences (I(x+1) - I(x-1)) / 2.
  cv::Sobel(left_, left_dx_, CV_32F, 1, 0, 1, 0.5, 0.0, cv::BORDER_REPLICATE);
  cv::Sobel(right_, right_dx_, CV_32F, 1, 0, 1, 0.5, 0.0, cv::BORDER_REPLICATE);
}

std::optional<RefinedDisparity> SubpixelRefiner::Refine(int u_image, int v_image, double disparity_px) const {
  const int u = u_image - origin_.x, v = v_image - origin_.y;
  const int h = options_.half_window_px;
  const int n = (2 * h + 1) * (2 * h + 1);
  const double d_int = std::round(disparity_px);
  const double start = disparity_px - d_int;
  // Both windows need their samples and the next column inside the image;
  // a slanted window's columns shift by up to max_slope * h more.
  const int margin = h + 2 + (options_.slanted ? static_cast<int>(std::ceil(options_.max_slope * h)) : 0);
  if (v - h < 0 || v + h >= left_.rows || u - margin < 0 || u + margin >= left_.cols || u - d_int - margin < 0 ||
      u - d_int + margin >= left_.cols) {
    return std::nullopt;
  }
  // Parameters: delta (the centre's disparity minus d_int), and with a
  // slanted window its change per column and per row, so that sample (i, j)
  // (row, column offsets) is shifted by delta + a j + b i. One Gauss-Newton
  // step solves the zero-mean normal equations (the windows' brightness
  // offset is not a disparity) for all of them.
  Eigen::Vector3d p(start, 0.0, 0.0);
  RefinedDisparity out;
  const int max_iterations = options_.slanted ? 2 * options_.max_iterations : options_.max_iterations;
  for (int iteration = 0; iteration < max_iterations; ++iteration) {
    // One pass: the zero-mean normal equations from the sums,
    // sum (j - mean j)(j - mean j)^T = sum j j^T - n mean_j mean_j^T, likewise for j e.
    double sum_e = 0.0;
    Eigen::Vector3d sum_j = Eigen::Vector3d::Zero(), sum_je = Eigen::Vector3d::Zero();
    Eigen::Matrix3d sum_jj = Eigen::Matrix3d::Zero();
    for (int i = -h; i <= h; ++i) {
      const float* l = left_.ptr<float>(v + i);
      const float* r = right_.ptr<float>(v + i);
      const float* lx = left_dx_.ptr<float>(v + i);
      const float* rx = right_dx_.ptr<float>(v + i);
      for (int j = -h; j <= h; ++j) {
        const double shift = p(0) + p(1) * j + p(2) * i;
        const double xl = u + j + 0.5 * shift;
        const double xr = u + j - d_int - 0.5 * shift;
        // e = I_L(xl) - I_R(xr); de/d shift = (I_L'(xl) + I_R'(xr)) / 2.
        const double e = SampleRow(l, xl) - SampleRow(r, xr);
        const double g = 0.5 * (SampleRow(lx, xl) + SampleRow(rx, xr));
        const Eigen::Vector3d jk(g, g * j, g * i);
        sum_e += e;
        sum_j += jk;
        sum_je += e * jk;
        sum_jj.noalias() += jk * jk.transpose();
      }
    }
    const Eigen::Vector3d mean_j = sum_j / n;
    const Eigen::Matrix3d jj = sum_jj - n * mean_j * mean_j.transpose();
    const Eigen::Vector3d je = sum_je - sum_e * mean_j;
    if (!(jj(0, 0) >= options_.min_gradient_energy)) return std::nullopt;
    Eigen::Vector3d step = Eigen::Vector3d::Zero();
    if (!options_.slanted) {
      step(0) = -je(0) / jj(0, 0);
    } else {
      step = -jj.ldlt().solve(je);
      if (!step.allFinite()) return std::nullopt;
    }
    p += step;
    out.iterations = iteration + 1;
    if (!(std::abs(p(0) - start) <= options_.max_correction_px)) return std::nullopt;
    if (!(std::abs(p(1)) <= options_.max_slope) || !(std::abs(p(2)) <= options_.max_slope)) return std::nullopt;
    if (std::abs(step(0)) < options_.tolerance_px && std::abs(step(1)) * h < options_.tolerance_px &&
        std::abs(step(2)) * h < options_.tolerance_px) {
      break;
    }
  }
  out.u_px = u_image + 0.5 * p(0);
  out.disparity_px = d_int + p(0);
  out.slope_u = p(1);
  out.slope_v = p(2);
  return out;
}

}  // namespace aar
