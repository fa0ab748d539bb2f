#pragma once
// How an MSAA level is produced on a device (docs/rendering.md, "MSAA").
//
// A level the device supports natively is rendered in one pass with that many
// samples. Any other level L is composed from k = L / n jittered passes of the
// largest native count n that divides L; the passes are resolved and averaged
// in linear colour. Sub-pixel offsets: the native pattern of n samples is an
// n-rooks pattern (one sample per row and column of an n x n grid of cells,
// true of the Vulkan standard 4-, 8- and 16-sample locations); pass j moves
// every sample to sub-cell (sigma_j, tau_j) of a k x k split of its cell, with
// sigma_j = j and tau_j = the k-bit bit reversal of j. The union of all
// passes is then an (n k)-rooks pattern whose samples are also stratified
// inside each native cell (a Hammersley set), i.e. well spread.

#include <string>
#include <vector>

namespace aar {

struct Vec2 {
  double x = 0.0;
  double y = 0.0;
};

struct MsaaPlan {
  int level = 1;                 ///< requested samples per pixel
  int native_samples = 1;        ///< samples per pass (a native count of the device)
  int passes = 1;                ///< jittered passes averaged
  std::vector<Vec2> offsets_px;  ///< per pass: sub-pixel jitter added to every sample [px]
  std::string method;            ///< "native" or "composed"
};

/// Levels the command line accepts.
bool IsSupportedMsaaLevel(int level);

/// Throws aar::Error naming --msaa when `level` is not a supported level.
void CheckMsaaLevel(int level);

/// Vulkan standard sample locations for n = 1, 2, 4, 8, 16, in pixel units
/// from the top-left corner of the pixel (Vulkan spec, "Standard Sample Locations").
std::vector<Vec2> StandardSampleLocations(int samples);

/// Plans `level` for a device whose colour attachments support the sample
/// counts in `native_counts` (e.g. {1, 4} on lavapipe). Throws aar::Error for
/// an unsupported level.
MsaaPlan PlanMsaa(int level, const std::vector<int>& native_counts);

/// Every sample position of the plan inside the pixel, [0,1)^2, pass by pass.
std::vector<Vec2> CompositeSamplePattern(const MsaaPlan& plan);

}  // namespace aar
