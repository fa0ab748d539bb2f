#pragma once
// Rectification and disparity maps (thesis 3.4): OpenCV block matching (or
// semi-global matching) on the rectified left/right images, then OpenCV's
// speckle filter.

#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "aar/stereo_calibration.h"

namespace aar {

enum class DisparityAlgorithm {
  kBlockMatching,  ///< cv::StereoBM (the thesis)
  kSemiGlobal,     ///< cv::StereoSGBM (MODE_SGBM), for comparison
};

struct DisparityOptions {
  DisparityAlgorithm algorithm = DisparityAlgorithm::kBlockMatching;
  int min_disparity = 0;       ///< smallest disparity searched [px]
  int num_disparities = 48;    ///< disparities searched, multiple of 16 (thesis 3.4: 48) [px]
  int block_size = 9;          ///< matching window side, odd (thesis 3.4: 9) [px]
  int pre_filter_cap = 31;     ///< BM: x-Sobel pre-filter clip (OpenCV default); SGBM: derivative clip
  int texture_threshold = 10;  ///< BM only: minimum summed |x-Sobel| over the window (OpenCV default)
  int uniqueness_ratio =
      15;  ///< best cost must beat the second best (outside +-1 px) by this many percent (OpenCV BM default)
  /// Pixels whose disparity is at or below this are background beyond the
  /// stereo range and are marked invalid before the speckle filter, like the
  /// texture-less sky. Against a textured background (terrain kilometres
  /// away, true disparity ~0.05 px) the few wrong matches then stand alone
  /// and the speckle filter removes them, and halo removal sees the same
  /// invalid border as against the sky. Negative = off (the thesis; the
  /// default preset uses 0.5 px: 900 m with the default rig's f b = 450 px m,
  /// beyond the re-projection's 750 m anyway) [px].
  double background_disparity_px = -1.0;
  /// Speckle filter (thesis 3.4), applied with cv::filterSpeckles after
  /// matching (the matchers' built-in speckle filtering is switched off: BM
  /// takes its range in 1/16 px, SGBM in px, so it is done once here with
  /// explicit units). Connected regions (4-neighbours whose disparities differ
  /// by at most speckle_range_px) with fewer than speckle_window_size pixels
  /// are marked invalid. 0 disables the filter.
  int speckle_window_size = 100;  ///< largest region removed [pixels]
  double speckle_range_px = 2.0;  ///< neighbour disparity difference within one region [px]
  int disp12_max_diff = -1;       ///< left-right consistency check tolerance [px]; -1 = off (OpenCV default)
  int sgbm_p1 = 8 * 9 * 9;        ///< SGBM smoothness penalty for +-1 px changes (8 * block_size^2, OpenCV sample)
  int sgbm_p2 = 32 * 9 * 9;       ///< SGBM smoothness penalty for larger changes (32 * block_size^2)

  /// Throws aar::Error naming the first value out of range.
  void Check() const;
  /// Value OpenCV writes for pixels without a disparity, in 1/16 px: (min_disparity - 1) * 16.
  int InvalidValue16() const { return (min_disparity - 1) * 16; }
};

/// The mean error that a matcher's fixed-point rounding adds to its
/// disparities [px]. StereoBM interpolates the cost minimum in 1/256 px and
/// converts to its 1/16 px output with (d + 15) >> 4 (OpenCV stereobm.cpp),
/// which rounds up: for a sub-pixel position spread evenly over the 16 values
/// of d mod 16, the output exceeds d / 256 by (15 - 7.5) / 256 = 15/512 px
/// (0.0293 px) on average. StereoSGBM rounds to nearest: 0.
double MatcherRoundingBiasPx(DisparityAlgorithm algorithm);

/// Rectifies image pairs with one calibration: the undistort-rectify maps of
/// both cameras are built once (cv::initUndistortRectifyMap with R1/P1 and
/// R2/P2, CV_16SC2 fixed-point maps) and applied with cv::remap, INTER_LINEAR,
/// constant black border.
class Rectifier {
 public:
  explicit Rectifier(const StereoCalibration& calibration);

  /// Rectified 8-bit grayscale images (input gray or BGR, converted with
  /// cv::cvtColor BGR2GRAY first). Sizes must match the calibration's.
  void Rectify(const cv::Mat& left, const cv::Mat& right, cv::Mat& rect_left_gray, cv::Mat& rect_right_gray) const;
  /// The same for the pixels of `region` of the rectified images only (an
  /// empty region: all); the outputs are region-sized.
  void Rectify(const cv::Mat& left, const cv::Mat& right, cv::Mat& rect_left_gray, cv::Mat& rect_right_gray,
               const cv::Rect& region) const;

  cv::Size image_size() const { return image_size_; }

 private:
  // Which input pixels each 32 x 32 block of a rectification map reads (a
  // sample and its right and lower neighbours, clipped to the image), so
  // that a region converts to grey only the part of the inputs it needs.
  struct SourceBlocks {
    int block_columns = 0;
    std::vector<cv::Rect> reads;  // row-major over the map's blocks
    cv::Rect Needed(const cv::Rect& region) const;
  };
  static SourceBlocks BlocksOf(const cv::Mat& map1, cv::Size image_size);

  cv::Size image_size_;
  cv::Mat left_map1_, left_map2_, right_map1_, right_map2_;
  SourceBlocks left_blocks_, right_blocks_;
};

/// Converts an 8-bit gray, BGR or BGRA image to gray with cv::cvtColor.
/// Errors name the image as `name`.
cv::Mat ToGrayscale(const cv::Mat& image, const std::string& name = "image");

struct DisparityMap {
  cv::Mat disparity16;        ///< CV_16S, disparity * 16 in rect_left pixels; InvalidValue16() where none
  int invalid_value16 = -16;  ///< the value marking invalid pixels in disparity16
};

/// Disparity of the rectified left image against the rectified right image
/// (8-bit gray, same size). Deterministic for a given thread count; the main
/// program runs single-threaded.
DisparityMap ComputeDisparity(const cv::Mat& rect_left_gray, const cv::Mat& rect_right_gray,
                              const DisparityOptions& options);

}  // namespace aar
