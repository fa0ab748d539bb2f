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

#include <cstdint>
#include <opencv2/core.hpp>
#include <optional>
#include <vector>

namespace aar {

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

  /// Throws aar::Error naming the first invalid field.
  void Check() const;
};

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

  cv::Mat left8_, right8_;  // the rectified 8-bit images (shared, not copied)
  // CV_32FC2 (intensity, horizontal central difference) per pixel, filled
  // row by row as windows need them: a frame's receiver covers a fraction of
  // the rows, and converting the whole image costs more than refining.
  mutable cv::Mat left_, right_;
  mutable std::vector<uint8_t> row_ready_;
  SubpixelOptions options_;
  cv::Point origin_;
};

}  // namespace aar
