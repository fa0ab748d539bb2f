#pragma once
// Output encodings of rendered views (docs/dataset-format.md).

#include <filesystem>
#include <opencv2/core.hpp>
#include <string>

#include "aar/image.h"

namespace aar {

/// Linear RGB floats -> 8-bit sRGB, BGR channel order (OpenCV), exact
/// round-to-nearest of the sRGB transfer function.
cv::Mat ToSrgb8(const LinearImage& image);

/// Radiometric 16-bit: the first channel (a brightness temperature [K]) x
/// 100, rounded, clamped to [0, 65535]: 0.01 K per count, one channel.
cv::Mat ToCentikelvin16(const LinearImage& image);

/// PNG settings (lossless: the same pixels either way).
enum class PngStrategy {
  /// libpng's adaptive filter choice, zlib level 3, Z_DEFAULT_STRATEGY: the
  /// flat sky and the masks, so their files stay the bytes of every earlier
  /// dataset.
  kDefault,
  /// OpenCV's speed-tuned settings (no level given: the SUB filter on every
  /// row, zlib level 1) with Z_RLE: views over a textured background, whose
  /// deflate otherwise took twice the flat sky's time beside the rendering.
  /// On a 1024 x 768 x4 terrain view: 52 against 88 ms (level 3, Z_RLE,
  /// adaptive filters), 4 % larger (docs/performance.md).
  kFast,
};

/// PNG bytes of an 8-bit image (ToSrgb8's BGR, or a one-channel mask) or of ToCentikelvin16's.
std::string EncodePng(const cv::Mat& bgr8, PngStrategy strategy = PngStrategy::kDefault);

/// Writes the depth of a ground-truth image as a one-channel 32-bit float
/// OpenEXR file (channel "Y", metres along the optical axis, 0 = no surface;
/// no time stamp, so byte-identical for the same depth), atomically, with
/// OpenImageIO; returns the file's SHA-256.
std::string WriteDepthExr(const std::filesystem::path& path, const GroundTruthImage& truth);

}  // namespace aar
