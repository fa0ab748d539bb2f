#pragma once
// Reading a dataset's PNG images: the SHA-256 checks (opened_dataset.h,
// OpenedDataset::ReadFile), the chunk structure (png_check.h), then decoding.

#include <opencv2/imgcodecs.hpp>
#include <string>
#include <string_view>

#include "aar/opened_dataset.h"

namespace aar {

/// Decodes a PNG whose bytes the caller has verified (by the manifest's
/// SHA-256 and CheckPngStructure's chunk CRCs) as cv::imdecode(bytes, flags)
/// does. 8-bit non-interlaced grey and RGB files with IMREAD_COLOR,
/// IMREAD_UNCHANGED or (grey files) IMREAD_GRAYSCALE are decoded with libpng
/// without checking the chunks' CRCs and the zlib stream's Adler-32 again
/// (Adler-32 alone took a sixth of a CONOPS frame's decode); others go to
/// cv::imdecode. Empty when the bytes do not decode.
cv::Mat DecodeVerifiedPng(std::string_view bytes, int flags);

/// Reads the image `ref` of a sidecar of `dataset`; throws aar::Error naming
/// the file when it is missing, changed, not a whole PNG or undecodable
/// ("<path>: cannot decode <what>").
cv::Mat ReadListedImage(const OpenedDataset& dataset, const FileRef& ref, int flags, const std::string& what);

/// A thermal pair (a rig with lwir: one-channel 16-bit PNGs, 0.01 K per
/// count) as the 8-bit BGR images the matcher takes: one linear window for
/// both, as a camera's automatic gain control maps its scene, the pair's
/// coldest count to 0 and its hottest to 255 (rounded); `where` names the
/// file of an image that is not one-channel 16-bit.
void WindowThermalPair(cv::Mat& left, cv::Mat& right, const std::string& where);
/// One thermal image windowed alone, its coldest count to 0 and hottest to
/// 255 (a calibration board's, whose corners are found image by image).
void WindowThermalImage(cv::Mat& image, const std::string& where);

}  // namespace aar
