#pragma once
// Reading a dataset's PNG images: the SHA-256 checks (dataset.h,
// ReadListedFile), the chunk structure (png_check.h), then decoding.

#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <string>

#include "aar/dataset.h"

namespace aar {

/// Reads the image `ref` of a sidecar of `dataset`; throws aar::Error naming
/// the file when it is missing, changed, not a whole PNG or undecodable
/// ("<path>: cannot decode <what>").
cv::Mat ReadListedImage(const std::filesystem::path& dataset, const Manifest& manifest, const FileRef& ref, int flags,
                        const std::string& what);

}  // namespace aar
