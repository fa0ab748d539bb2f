#pragma once
// Removal of matches over clipped pixels (docs/analysis.md, "Sun glints").
//
// A pixel at the image's white level (a glint of the sun, a saturated
// sensor) has lost the texture that would say where the surface is: the
// block matcher's cost over a window that holds it compares nothing inside
// the clipped area, and the area's edge is where the light, not the surface,
// crosses the white level, at a different place in each camera. So a
// disparity whose matching window reaches a clipped pixel, in the left image
// at its own pixel or in the right image at the column it matched, is
// dropped. Images without clipped pixels are unchanged.

#include <opencv2/core.hpp>

#include "aar/analyzer/disparity.h"

namespace aar {

struct ClippedPixelOptions {
  /// Gray values at or above this are clipped: 255, the 8-bit images' white.
  int clip_level = 255;
  /// Matches this close (Chebyshev) to a clipped pixel go [px]: the matching
  /// window's half width plus StereoBM's pre-filter pixel (HaloRadiusPx).
  int radius_px = 5;

  /// Throws aar::Error naming the first invalid field.
  void Check() const;
};

/// Marks invalid, in place, every valid disparity of a CV_16S map (disparity
/// * 16, the size of the rectified 8-bit gray images) within
/// options.radius_px of a clipped pixel of `rect_left` at its own pixel or of
/// `rect_right` at its matched column (u - d, rounded); returns how many.
size_t RemoveClippedMatches(cv::Mat& disparity16, int invalid_value16, const cv::Mat& rect_left,
                            const cv::Mat& rect_right, const ClippedPixelOptions& options);

}  // namespace aar
