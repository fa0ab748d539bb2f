#pragma once
// Output encodings of rendered views (docs/dataset-format.md).

#include <filesystem>
#include <opencv2/core.hpp>
#include <string>

#include "aar/renderer/scene_renderer.h"

namespace aar {

/// Linear RGB floats -> 8-bit sRGB, BGR channel order (OpenCV), exact
/// round-to-nearest of the sRGB transfer function.
cv::Mat ToSrgb8(const LinearImage& image);

/// zlib's strategy for a PNG's compressed stream (both at level 3, lossless:
/// the same pixels either way). Run-length suits views over a textured
/// background: on 1024 x 768 views it was 1.3-1.5x faster and 13-14 % smaller
/// over terrain, clouds and the plain ground of `sky` (docs/performance.md);
/// the flat sky keeps the default, so its files stay the bytes of every
/// earlier dataset.
enum class PngStrategy {
  kDefault,    ///< Z_DEFAULT_STRATEGY
  kRunLength,  ///< Z_RLE
};

/// PNG bytes of an 8-bit image (ToSrgb8's BGR, or a one-channel mask).
std::string EncodePng(const cv::Mat& bgr8, PngStrategy strategy = PngStrategy::kDefault);

/// Writes the depth of a ground-truth image as a one-channel 32-bit float
/// OpenEXR file (channel "Y", metres along the optical axis, 0 = no surface;
/// no time stamp, so byte-identical for the same depth), atomically, with
/// OpenImageIO; returns the file's SHA-256.
std::string WriteDepthExr(const std::filesystem::path& path, const GroundTruthImage& truth);

}  // namespace aar
