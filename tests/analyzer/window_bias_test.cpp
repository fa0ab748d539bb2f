// The window-bias prediction against the refinement's own error on a
// synthetic curved surface.

#include "aar/analyzer/window_bias.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <opencv2/core.hpp>
#include <vector>

#include "aar/analyzer/subpixel.h"
#include "aar/error.h"
#include "synthetic_texture.h"
#include "test_meshes.h"

namespace aar {
namespace {

// A ridge across the image: disparity d(x) = peak - curvature (x - ridge)^2
// at left column x (a cylinder's profile seen side-on, to second order).
struct Ridge {
  double peak, curvature, ridge;
  double At(double x) const { return peak - curvature * (x - ridge) * (x - ridge); }
};

constexpr int kWidth = 200, kHeight = 80;

// The left image shows the texture at (x, y); the right one at column x the
// surface point whose left column x_l satisfies x_l - d(x_l) = x (found by
// fixed-point iteration: |d'| < 1 here).
void RenderPair(const test::Texture& texture, const Ridge& ridge, cv::Mat& left, cv::Mat& right) {
  left.create(kHeight, kWidth, CV_8UC1);
  right.create(kHeight, kWidth, CV_8UC1);
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      double x_left = x + ridge.At(x);
      for (int k = 0; k < 50; ++k) x_left = x + ridge.At(x_left);
      left.at<uchar>(y, x) = cv::saturate_cast<uchar>(texture(x, y));
      right.at<uchar>(y, x) = cv::saturate_cast<uchar>(texture(x_left, y));
    }
  }
}

TEST(WindowBias, PredictsTheRefinementsErrorOnACurvedSurface) {
  // The refinement's affine window on a concave disparity profile returns
  // less than the centre's disparity; the prediction from the true field and
  // the images' gradients removes most of that error.
  const Ridge ridge{12.3, 0.004, 100.0};
  double raw_sum = 0.0, corrected_sum = 0.0, raw_squared = 0.0, corrected_squared = 0.0;
  size_t count = 0;
  for (unsigned seed = 1; seed <= 3; ++seed) {
    cv::Mat left, right;
    RenderPair(test::Texture(seed), ridge, left, right);
    cv::Mat model(left.size(), CV_32F);
    for (int y = 0; y < kHeight; ++y) {
      for (int x = 0; x < kWidth; ++x) model.at<float>(y, x) = static_cast<float>(ridge.At(x));
    }
    const SubpixelRefiner refiner(left, right, SubpixelOptions{});
    std::vector<Eigen::Vector3d> pixels;
    std::vector<double> truth;
    for (int v = 20; v < 60; v += 2) {
      for (int u = 60; u <= 140; u += 2) {
        const auto refined = refiner.Refine(u, v, ridge.At(u) + 0.2);
        if (!refined) continue;
        pixels.emplace_back(refined->u_px, v, refined->disparity_px);
        truth.push_back(ridge.At(refined->u_px));
      }
    }
    const std::vector<double> bias = PredictWindowBias(left, right, model, {0, 0}, pixels, WindowBiasOptions{});
    ASSERT_EQ(bias.size(), pixels.size());
    for (size_t k = 0; k < pixels.size(); ++k) {
      const double raw = pixels[k].z() - truth[k], corrected = raw - bias[k];
      raw_sum += raw;
      corrected_sum += corrected;
      raw_squared += raw * raw;
      corrected_squared += corrected * corrected;
      ++count;
    }
  }
  const double n = static_cast<double>(count);
  std::printf("%zu points: error mean %+.4f rms %.4f px raw, %+.4f / %.4f corrected\n", count, raw_sum / n,
              std::sqrt(raw_squared / n), corrected_sum / n, std::sqrt(corrected_squared / n));
  EXPECT_GT(count, 1500u);
  // Uniform weights would give -curvature h (h + 1) / 3 = -0.027 px.
  EXPECT_LT(raw_sum / n, -0.015);
  EXPECT_LT(std::abs(corrected_sum / n), 0.2 * std::abs(raw_sum / n));
  EXPECT_LT(corrected_squared, 0.5 * raw_squared);
}

TEST(WindowBias, ModelDisparityOfAPlaneFacingTheCameras) {
  // A 4 m x 4 m box face 20 m ahead: d = f b / z = 900 * 0.5 / 20 inside its
  // outline, NaN around it; in a region, the same values at shifted pixels.
  TriangleMesh box;
  test::AddBox(box, Eigen::Vector3d(0.0, 0.0, 21.0), Eigen::Vector3d(2.0, 2.0, 1.0));
  StereoCalibration calibration;
  calibration.P1 = (cv::Mat_<double>(3, 4) << 900, 0, 100, 0, 0, 900, 80, 0, 0, 0, 1, 0);
  calibration.Q = (cv::Mat_<double>(4, 4) << 1, 0, 0, -100, 0, 1, 0, -80, 0, 0, 0, 900, 0, 0, 2, 0);
  const cv::Rect whole(0, 0, 200, 160), part(60, 50, 60, 40);
  const cv::Mat d = ModelDisparity(box, calibration, Eigen::Isometry3d::Identity(), whole, 0.1);
  const cv::Mat p = ModelDisparity(box, calibration, Eigen::Isometry3d::Identity(), part, 0.1);
  EXPECT_NEAR(d.at<float>(80, 100), 22.5, 1e-4);
  EXPECT_TRUE(std::isnan(d.at<float>(80, 5)));  // 95 px left of centre: 2.1 m at 20 m, off the face
  EXPECT_EQ(d.at<float>(70, 90), p.at<float>(70 - part.y, 90 - part.x));
}

TEST(WindowBias, RejectsInvalidOptions) {
  WindowBiasOptions options;
  options.min_model_fraction = 0.0;
  EXPECT_THROW(options.Check(), Error);
  options.min_model_fraction = 0.5;
  options.max_bias_px = 0.0;
  EXPECT_THROW(options.Check(), Error);
}

}  // namespace
}  // namespace aar
