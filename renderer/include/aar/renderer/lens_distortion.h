#pragma once
// Rendering a camera with lens distortion (docs/rendering.md, "Lens
// distortion"): the scene is rendered by the ideal pinhole camera with the
// same focal lengths and principal point, on an image grown by a margin that
// covers the distorted frame's field of view; each distorted output pixel then
// takes the pinhole image at the undistorted position of its centre (inverse
// map, Newton's method, lens.h). Colour is resampled in linear light with a
// separable Lanczos-3 filter whose footprint follows the inverse map's
// Jacobian (never narrower than one pinhole pixel, so minified parts do not
// alias); depth, object ids and silhouettes take the nearest pinhole sample,
// never blended. Pure CPU code, deterministic.

#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "aar/image.h"
#include "aar/renderer/view_effect.h"
#include "aar/rig.h"

namespace aar {

/// Pixels each side that the pinhole image extends beyond the distorted one.
struct PixelMargin {
  int left = 0, top = 0, right = 0, bottom = 0;
};

inline constexpr int kLanczosLobes = 3;         ///< Lanczos-a filter, a = 3 (support +-3 source pixels at scale 1)
inline constexpr int kMaxPinholeSidePx = 8192;  ///< largest pinhole render side (keeps the Vulkan images bounded)

class LensResampler : public ViewEffect {
 public:
  /// Inverse map of one distorted camera. `margin` must cover the filter
  /// footprint of every output pixel (RequiredMargin); larger is fine, so
  /// both cameras of a rig can share one pinhole image size. Throws
  /// aar::Error naming `where` when a pixel has no undistorted preimage.
  LensResampler(const Intrinsics& distorted, const PixelMargin& margin, const std::string& where);

  /// The margin one camera needs (source footprint of every output pixel, plus one pixel).
  static PixelMargin RequiredMargin(const Intrinsics& distorted, const std::string& where);

  /// The pinhole camera the scene is rendered with: no distortion, the same
  /// focal lengths, image grown by the margin, principal point moved with it.
  const Intrinsics& pinhole() const { return pinhole_; }

  /// The distorted view of a pinhole render (pinhole() sized). The last
  /// render and its view are kept: the next one recomputes only the output
  /// pixels whose filter footprint reaches a pinhole pixel that changed (the
  /// background is the same from frame to frame), and copies the rest, the
  /// same bytes a whole resampling gives.
  LinearImage ResampleColor(const LinearImage& pinhole) const;
  /// The view effect: ResampleColor (the exposure does not matter).
  LinearImage Apply(const LinearImage& pinhole, const SensorExposure&) const override { return ResampleColor(pinhole); }
  /// Depth and ids of the nearest pinhole sample, never blended.
  GroundTruthImage ResampleTruth(const GroundTruthImage& pinhole) const;

 private:
  int width_ = 0;  // distorted image size
  int height_ = 0;
  Intrinsics pinhole_;
  // Per output pixel, row-major: the source position in the pinhole image
  // (OpenCV pixel coordinates) and the filter footprint scale (>= 1) per axis.
  std::vector<double> source_x_, source_y_;
  std::vector<float> scale_x_, scale_y_;
  double max_reach_y_ = 0.0;  // the filter's largest reach in rows [px]
  // The last pinhole render and its resampled view (ResampleColor).
  struct Cache {
    std::mutex mutex;
    LinearImage in, out;
  };
  std::unique_ptr<Cache> cache_ = std::make_unique<Cache>();

  // Output pixel i of `in` into `out` (`run`: ResampleColor's runs of equal pixels).
  void ResamplePixel(size_t i, const LinearImage& in, const std::vector<uint32_t>& run, LinearImage& out) const;
};

}  // namespace aar
