#include "aar/renderer/image_encode.h"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <opencv2/imgcodecs.hpp>
#include <vector>

#include "aar/error.h"
#include "aar/file_io.h"
#include "aar/renderer/scene_model.h"

namespace aar {
namespace {

// thresholds[i] = linear value where the 8-bit sRGB code changes from i-1 to
// i, i.e. SrgbToLinear((i - 0.5) / 255); the code of v is the number of
// thresholds at or below it, minus one (0 below thresholds[1]).
const std::array<float, 256>& Srgb8Thresholds() {
  static const std::array<float, 256> thresholds = [] {
    std::array<float, 256> t{};
    t[0] = -1.0f;
    for (int i = 1; i < 256; ++i) t[i] = SrgbToLinear((static_cast<float>(i) - 0.5f) / 255.0f);
    return t;
  }();
  return thresholds;
}

// The binary search over the thresholds, exact for every float (NaN: 255).
uint8_t Srgb8BySearch(float v) {
  const auto& t = Srgb8Thresholds();
  return static_cast<uint8_t>(std::max<std::ptrdiff_t>(0, std::upper_bound(t.begin(), t.end(), v) - t.begin() - 1));
}

// The same codes, faster: between thresholds[1] and thresholds[255] a
// positive float's bits grow with its value, so the top bits (exponent and 8
// mantissa bits) name a bucket of floats whose smallest member's code is
// tabulated (by the search); the thresholds above it are then stepped over,
// at most a few.
constexpr int kBucketShift = 15;

struct Srgb8Buckets {
  uint32_t first = 0;          // bucket of thresholds[1]
  std::vector<uint8_t> codes;  // per bucket from `first`: the code of its smallest float
};

const Srgb8Buckets& Buckets() {
  static const Srgb8Buckets buckets = [] {
    const auto& t = Srgb8Thresholds();
    Srgb8Buckets b;
    b.first = std::bit_cast<uint32_t>(t[1]) >> kBucketShift;
    const uint32_t last = std::bit_cast<uint32_t>(t[255]) >> kBucketShift;
    for (uint32_t bucket = b.first; bucket <= last; ++bucket) {
      // The first bucket starts below thresholds[1]: its smallest float of interest is thresholds[1].
      const float smallest = std::max(t[1], std::bit_cast<float>(bucket << kBucketShift));
      b.codes.push_back(Srgb8BySearch(smallest));
    }
    return b;
  }();
  return buckets;
}

uint8_t Srgb8(float v, const std::array<float, 256>& t, const Srgb8Buckets& buckets) {
  if (!(v < t[255])) return 255;  // and NaN, as the search
  if (v < t[1]) return 0;
  int code = buckets.codes[(std::bit_cast<uint32_t>(v) >> kBucketShift) - buckets.first];
  while (v >= t[code + 1]) ++code;  // stops below 255: v < thresholds[255]
  return static_cast<uint8_t>(code);
}

}  // namespace

cv::Mat ToSrgb8(const LinearImage& image) {
  const auto& thresholds = Srgb8Thresholds();
  const Srgb8Buckets& buckets = Buckets();
  cv::Mat out(image.height, image.width, CV_8UC3);
  for (int y = 0; y < image.height; ++y) {
    uint8_t* row = out.ptr<uint8_t>(y);
    const float* src = &image.rgb[static_cast<size_t>(y) * image.width * 3];
    for (int x = 0; x < image.width; ++x) {
      for (int c = 0; c < 3; ++c) row[x * 3 + (2 - c)] = Srgb8(src[x * 3 + c], thresholds, buckets);
    }
  }
  return out;
}

cv::Mat ToCentikelvin16(const LinearImage& image) {
  cv::Mat out(image.height, image.width, CV_16UC1);
  for (int y = 0; y < image.height; ++y) {
    uint16_t* row = out.ptr<uint16_t>(y);
    for (int x = 0; x < image.width; ++x) {
      const double kelvin = image.rgb[(static_cast<size_t>(y) * image.width + x) * 3];
      row[x] = static_cast<uint16_t>(std::clamp(std::lround(100.0 * kelvin), 0L, 65535L));
    }
  }
  return out;
}

std::string EncodePng(const cv::Mat& bgr8, PngStrategy strategy) {
  std::vector<uint8_t> bytes;
  // Without IMWRITE_PNG_COMPRESSION OpenCV (grfmt_png.cpp) tunes libpng for
  // speed: PNG_FILTER_SUB and Z_BEST_SPEED.
  const std::vector<int> settings = strategy == PngStrategy::kFast
                                        ? std::vector<int>{cv::IMWRITE_PNG_STRATEGY, cv::IMWRITE_PNG_STRATEGY_RLE}
                                        : std::vector<int>{cv::IMWRITE_PNG_COMPRESSION, 3};
  if (!cv::imencode(".png", bgr8, bytes, settings)) throw Error("PNG encoding failed");
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
