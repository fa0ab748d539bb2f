#include "aar/analyzer/subpixel.h"

#include <cmath>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "aar/error.h"

namespace aar {
namespace {

// Linear interpolation along a row at column x (0 <= x < cols - 1).
inline float SampleRow(const float* row, double x) {
  const int x0 = static_cast<int>(std::floor(x));
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
  // Both windows need their samples and the next column inside the image.
  const int margin = h + 2;
  if (v - h < 0 || v + h >= left_.rows || u - margin < 0 || u + margin >= left_.cols || u - d_int - margin < 0 ||
      u - d_int + margin >= left_.cols) {
    return std::nullopt;
  }
  std::vector<float> residual(static_cast<size_t>(n)), jacobian(static_cast<size_t>(n));
  double delta = start;
  RefinedDisparity out;
  for (int iteration = 0; iteration < options_.max_iterations; ++iteration) {
    double sum_e = 0.0, sum_j = 0.0;
    size_t k = 0;
    for (int i = -h; i <= h; ++i) {
      const float* l = left_.ptr<float>(v + i);
      const float* r = right_.ptr<float>(v + i);
      const float* lx = left_dx_.ptr<float>(v + i);
      const float* rx = right_dx_.ptr<float>(v + i);
      for (int j = -h; j <= h; ++j, ++k) {
        const double xl = u + j + 0.5 * delta;
        const double xr = u + j - d_int - 0.5 * delta;
        // e = I_L(xl) - I_R(xr); de/d delta = (I_L'(xl) + I_R'(xr)) / 2.
        residual[k] = SampleRow(l, xl) - SampleRow(r, xr);
        jacobian[k] = 0.5f * (SampleRow(lx, xl) + SampleRow(rx, xr));
        sum_e += residual[k];
        sum_j += jacobian[k];
      }
    }
    // Zero-mean (the windows' brightness offset is not a disparity).
    const double mean_e = sum_e / n, mean_j = sum_j / n;
    double jj = 0.0, je = 0.0;
    for (size_t m = 0; m < static_cast<size_t>(n); ++m) {
      const double jm = jacobian[m] - mean_j;
      jj += jm * jm;
      je += jm * (residual[m] - mean_e);
    }
    if (!(jj >= options_.min_gradient_energy)) return std::nullopt;
    const double step = -je / jj;
    delta += step;
    out.iterations = iteration + 1;
    if (!(std::abs(delta - start) <= options_.max_correction_px)) return std::nullopt;
    if (std::abs(step) < options_.tolerance_px) break;
  }
  out.u_px = u_image + 0.5 * delta;
  out.disparity_px = d_int + delta;
  return out;
}

}  // namespace aar
