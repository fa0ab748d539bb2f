#pragma once
// Symmetric sub-pixel disparity refinement.
//
// Block matchers fit a parabola to three matching costs around the integer
// minimum; for SAD-like costs this biases the result towards integers ("pixel
// locking", Shimizu and Okutomi 2001), and OpenCV's StereoBM then rounds up to
// 1/16 px. Here each disparity is refined by Gauss-Newton on the zero-mean
// sum of squared differences of the two rectified images over the matching
// window, with the shift split symmetrically between them: the left window is
// sampled at u + delta/2 and the right one at u - d_int - delta/2 around the
// nearest integer disparity d_int. Both images are then interpolated
// (linearly) at mirrored fractional offsets, so the smoothing of
// interpolation is the same in both and its bias cancels, instead of locking
// the estimate to integers as one-sided interpolation does (the
// "symmetric" / error-cancelling scheme of stereo and optical-flow
// refinement). The refined point is re-projected from the left pixel
// u + delta/2 with disparity d_int + delta.
//
// Linear interpolation still shifts the signal it interpolates by less than
// the fraction asked for (its phase lags at every frequency but the
// half-pixel), and the mirrored offsets add the two lags: the estimate
// overshoots |delta|, by up to 0.03 px on the renders' texture, in a pattern
// that flips sign where the nearest integer changes (frac(d) = 1/2). Across a
// far receiver, whose disparities span a few tenths of a pixel, that pattern
// is a gain error on the disparity differences, so a tilt.
// SubpixelInterpolation::kCubicBSpline interpolates each row with the cubic
// B-spline of the row (Unser, Aldroubi and Eden 1991: the recursive
// prefilter, mirror boundaries) and takes the gradient as the spline's own
// derivative. A cubic B-spline reproduces shifts of smooth signals almost
// exactly, but its prefilter amplifies high frequencies, so white noise
// interpolated at fraction a has a variance that depends on a, and the
// minimum of the window's squared differences is pulled towards the
// fractions where it is lowest. A Gaussian along the rows first
// (prefilter_sigma_px) makes that variance flat: 0.8 px is the smallest
// tenth of a pixel for which it varies by less than 2.5 % over a (the test
// SubpixelBSpline.PrefilterMakesNoiseVarianceFlat computes it).

#include <Eigen/Core>
#include <cstdint>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

namespace aar {

/// How a row is sampled between pixels (see above).
enum class SubpixelInterpolation {
  kLinear,        ///< linear interpolation, gradient from central differences
  kCubicBSpline,  ///< Gaussian prefilter along the row, then its cubic B-spline
};

struct SubpixelOptions {
  int half_window_px = 4;          ///< window (2h+1)^2; 4 = the 9x9 block of the thesis's matcher [px]
  int max_iterations = 4;          ///< Gauss-Newton steps at most (slanted windows: twice this)
  double tolerance_px = 0.01;      ///< stop when a step is smaller [px]
  double max_correction_px = 1.0;  ///< |delta - start| larger than this: refinement rejected [px]
  /// Summed squared horizontal gradient over the window below which the
  /// window has too little texture to refine [grey levels^2 / px^2].
  double min_gradient_energy = 100.0;
  /// Slanted window: also solve for the disparity's change per column and per
  /// row (see above); false: one shift for the whole window.
  bool slanted = true;
  /// Slanted window: |dd/du| and |dd/dv| above this reject the refinement (a
  /// surface that steep is seen edge-on) [px / px].
  double max_slope = 0.5;
  SubpixelInterpolation interpolation = SubpixelInterpolation::kLinear;
  /// kCubicBSpline: standard deviation of the Gaussian applied along each row
  /// before the spline (see above) [px]; 0 = none.
  double prefilter_sigma_px = 0.8;

  /// Throws aar::Error naming the first invalid field.
  void Check() const;
};

std::string ToString(SubpixelInterpolation interpolation);
/// "linear" or "bspline"; throws aar::Error naming the text otherwise.
SubpixelInterpolation ParseSubpixelInterpolation(const std::string& text);

/// kCubicBSpline's row preparation: `row` (n >= 2 samples) smoothed by a
/// Gaussian of `sigma_px` (0: none) and converted into the coefficients of
/// its cubic B-spline, both with mirror boundaries (x[-k] = x[k]).
void SplineRowCoefficients(const uint8_t* row, int n, double sigma_px, float* coefficients);
/// The spline with `coefficients` and its derivative at position x; needs
/// floor(x) - 1 >= 0 and floor(x) + 2 < the row's length.
void SampleSpline(const float* coefficients, double x, float* value, float* derivative);

/// A refined disparity: the left-image column it belongs to and its value.
struct RefinedDisparity {
  double u_px = 0.0;          ///< left column (rectified) of the point [px]
  double disparity_px = 0.0;  ///< refined disparity [px]
  double slope_u = 0.0;       ///< slanted window: d disparity / d column (0 otherwise)
  double slope_v = 0.0;       ///< slanted window: d disparity / d row (0 otherwise)
  int iterations = 0;
};

/// Refines disparities of one rectified pair (8-bit gray, same size). Not
/// thread-safe: Refine converts image rows on first use (one refiner per
/// frame and thread).
class SubpixelRefiner {
 public:
  /// `origin`: the rectified-image pixel of the images' top-left (a region).
  SubpixelRefiner(const cv::Mat& rect_left_gray, const cv::Mat& rect_right_gray, const SubpixelOptions& options,
                  cv::Point origin = {0, 0});

  /// Refines the disparity `disparity_px` of rectified left pixel (u, v);
  /// nullopt when the window leaves the image, lacks texture, or the estimate
  /// moves more than max_correction_px (the caller keeps or drops the point).
  std::optional<RefinedDisparity> Refine(int u, int v, double disparity_px) const;

 private:
  /// Converts rows first..last (once each) into left_ and right_.
  void PrepareRows(int first, int last) const;
  /// The window's residuals e = I_L - I_R and gradients (I_L' + I_R') / 2 at
  /// parameters p (see Refine), row-major, (2h+1)^2 of each.
  void SampleWindow(int u, int v, double d_int, const Eigen::Vector3d& p, float* e, float* g) const;
  /// The zero-mean Gauss-Newton normal equations of one window's samples.
  struct NormalEquations {
    Eigen::Matrix3d jj;
    Eigen::Vector3d je;
  };
  NormalEquations Normals(const float* e, const float* g) const;
  /// kCubicBSpline: the zero-mean squared horizontal gradient of the two
  /// unfiltered windows at integer disparity d_int (the texture test).
  double GradientEnergy(int u, int v, double d_int) const;

  cv::Mat left8_, right8_;  // the rectified 8-bit images (shared, not copied)
  // CV_32FC2 (intensity, horizontal central difference) per pixel, filled
  // row by row as windows need them: a frame's receiver covers a fraction of
  // the rows, and converting the whole image costs more than refining.
  mutable cv::Mat left_, right_;
  // kCubicBSpline: CV_32FC1 B-spline coefficients of the prefiltered rows.
  mutable cv::Mat left_spline_, right_spline_;
  mutable std::vector<uint8_t> row_ready_;
  // The current window's residuals and gradients (SampleWindow).
  mutable std::vector<float> residuals_, gradients_;
  SubpixelOptions options_;
  cv::Point origin_;
};

}  // namespace aar
