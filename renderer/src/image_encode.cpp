#include "aar/renderer/image_encode.h"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <array>
#include <opencv2/imgcodecs.hpp>

#include "aar/error.h"
#include "aar/file_io.h"

namespace aar {
namespace {

// thresholds[i] = linear value where the 8-bit sRGB code changes from i-1 to
// i, i.e. SrgbToLinear((i - 0.5) / 255); lookup by binary search is exact.
const std::array<float, 256>& Srgb8Thresholds() {
  static const std::array<float, 256> thresholds = [] {
    std::array<float, 256> t{};
    t[0] = -1.0f;
    for (int i = 1; i < 256; ++i) t[i] = SrgbToLinear((static_cast<float>(i) - 0.5f) / 255.0f);
    return t;
  }();
  return thresholds;
}

}  // namespace

cv::Mat ToSrgb8(const LinearImage& image) {
  const auto& thresholds = Srgb8Thresholds();
  cv::Mat out(image.height, image.width, CV_8UC3);
  for (int y = 0; y < image.height; ++y) {
    uint8_t* row = out.ptr<uint8_t>(y);
    const float* src = &image.rgb[static_cast<size_t>(y) * image.width * 3];
    for (int x = 0; x < image.width; ++x) {
      for (int c = 0; c < 3; ++c) {
        const float v = src[x * 3 + c];
        const auto it = std::upper_bound(thresholds.begin(), thresholds.end(), v);
        row[x * 3 + (2 - c)] = static_cast<uint8_t>(std::max<std::ptrdiff_t>(0, it - thresholds.begin() - 1));
      }
    }
  }
  return out;
}

std::string EncodePng(const cv::Mat& bgr8) {
  std::vector<uint8_t> bytes;
  if (!cv::imencode(".png", bgr8, bytes, {cv::IMWRITE_PNG_COMPRESSION, 3})) throw Error("PNG encoding failed");
  return std::string(bytes.begin(), bytes.end());
}

std::string WriteDepthExr(const std::filesystem::path& path, const GroundTruthImage& truth) {
  WriteFileAtomicWith(path, [&](const std::filesystem::path& temporary) {
    auto out = OIIO::ImageOutput::create("openexr");
    if (!out) throw Error(path.string() + ": OpenImageIO has no OpenEXR writer");
    OIIO::ImageSpec spec(truth.width, truth.height, 1, OIIO::TypeDesc::FLOAT);
    // "Y" (luminance) is the one-channel name OpenCV's EXR reader returns as
    // is (cv::imread(path, cv::IMREAD_UNCHANGED) gives CV_32FC1; "Z" reads as
    // zeros). An empty DateTime keeps OpenImageIO from stamping the current
    // time, so that the same depth gives the same bytes.
    spec.channelnames = {"Y"};
    spec.attribute("DateTime", "");
    spec.attribute("compression", "zip");
    spec.attribute("aar:units", "metres along the optical axis; 0 = no surface");
    if (!out->open(temporary.string(), spec) || !out->write_image(OIIO::TypeDesc::FLOAT, truth.depth_m.data()) ||
        !out->close()) {
      throw Error(path.string() + ": cannot write EXR (" + out->geterror() + ")");
    }
  });
  return Sha256File(path);
}

}  // namespace aar
