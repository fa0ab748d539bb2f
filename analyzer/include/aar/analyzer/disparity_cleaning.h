#pragma once
// Removal of the foreground-fattening halo of block matching.
//
// A block matcher gives a pixel the disparity of the strongest texture in its
// window. Next to a silhouette the window of a background pixel straddles the
// edge, so up to half a block of background (sky) around the receiver takes
// the receiver's disparity and re-projects to points in mid-air around the
// outline. StereoBM matches x-Sobel-filtered images, and the 3x3 pre-filter
// spreads an edge's texture one more pixel: the halo reaches
// block_size / 2 + 1 pixels past the silhouette (HaloRadiusPx). Against a uniform sky the pixels further out have no
// texture and are invalid; against a textured background they keep the background's disparity and the halo sits at a
// disparity jump. Either way the halo lies within half a block (block_size / 2, Chebyshev distance) of an invalid pixel
// or of a jump, so removing every valid pixel that close removes it, and costs the receiver only its own outermost half
// block where it meets such a boundary.

#include <opencv2/core.hpp>

#include "aar/analyzer/disparity.h"

namespace aar {

struct HaloRemovalOptions {
  /// Pixels within this Chebyshev distance of a boundary are removed [px];
  /// HaloRadiusPx (5 for the 9 px block) covers the whole halo.
  int radius_px = 5;
  /// Neighbours (4-connected) whose disparities differ by more than this mark
  /// a boundary [px]; on a smooth surface neighbouring disparities differ by
  /// a small fraction of a pixel.
  double max_jump_px = 1.0;

  /// Throws aar::Error naming the first invalid field.
  void Check() const;
};

/// The reach of the halo of a matcher: block_size / 2 + 1 (pre-filter) [px].
int HaloRadiusPx(const DisparityOptions& options);

/// Marks halo pixels of a CV_16S disparity map (disparity * 16) invalid, in
/// place; returns how many were removed.
size_t RemoveHalo(cv::Mat& disparity16, int invalid_value16, const HaloRemovalOptions& options);

}  // namespace aar
