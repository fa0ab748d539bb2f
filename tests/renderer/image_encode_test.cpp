// image_encode.h: ToSrgb8's bucketed lookup gives, for every float it can
// meet, the code of the exact search over the code thresholds
// SrgbToLinear((i - 0.5) / 255), so images encode to the same bytes; both PNG
// strategies are lossless and deterministic.

#include "aar/renderer/image_encode.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <opencv2/imgcodecs.hpp>
#include <random>
#include <vector>

#include "../test_support.h"
#include "aar/png_check.h"
#include "aar/renderer/scene_model.h"

namespace aar {
namespace {

// The reference: the number of thresholds at or below v, minus one (NaN: 255).
uint8_t SearchedCode(float v) {
  static const std::array<float, 256> t = [] {
    std::array<float, 256> thresholds{};
    thresholds[0] = -1.0f;
    for (int i = 1; i < 256; ++i) thresholds[i] = SrgbToLinear((static_cast<float>(i) - 0.5f) / 255.0f);
    return thresholds;
  }();
  return static_cast<uint8_t>(std::max<std::ptrdiff_t>(0, std::upper_bound(t.begin(), t.end(), v) - t.begin() - 1));
}

TEST(ImageEncode, Srgb8CodesEqualTheExactSearchForEveryKindOfValue) {
  std::vector<float> values = {0.0f,
                               -0.0f,
                               1.0f,
                               -1.0f,
                               2.0f,
                               1e-30f,
                               std::numeric_limits<float>::infinity(),
                               -std::numeric_limits<float>::infinity(),
                               std::numeric_limits<float>::quiet_NaN()};
  for (int i = 1; i < 256; ++i) {  // each threshold and its neighbouring floats
    const float t = SrgbToLinear((static_cast<float>(i) - 0.5f) / 255.0f);
    for (float v : {std::nextafter(t, -1.0f), t, std::nextafter(t, 2.0f)}) values.push_back(v);
  }
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> near_range(-0.05f, 1.05f);
  for (int i = 0; i < 200000; ++i) values.push_back(near_range(rng));
  while (values.size() % 3 != 0) values.push_back(0.5f);
  LinearImage image;
  image.width = static_cast<int>(values.size() / 3);
  image.height = 1;
  image.rgb = values;
  const cv::Mat bgr = ToSrgb8(image);
  size_t checked = 0;
  for (size_t i = 0; i < values.size(); ++i) {
    const uint8_t code = bgr.at<cv::Vec3b>(0, static_cast<int>(i / 3))[2 - static_cast<int>(i % 3)];
    ASSERT_EQ(code, SearchedCode(values[i])) << "value " << values[i];
    ++checked;
  }
  EXPECT_GT(checked, 200000u);
}

// Both PNG settings are lossless: the PNGs decode to the image encoded,
// and each encodes the same image to the same bytes every time.
TEST(ImageEncode, FastPngDecodesToTheSamePixels) {
  cv::Mat image(96, 128, CV_8UC3);
  std::mt19937 rng(11);
  for (int y = 0; y < image.rows; ++y) {
    for (int x = 0; x < image.cols; ++x) {
      const int field = (x / 16 + y / 16) % 4 * 40;  // fields with noise, like terrain
      for (int c = 0; c < 3; ++c) image.at<cv::Vec3b>(y, x)[c] = static_cast<uint8_t>(field + 30 * c + rng() % 24);
    }
  }
  for (PngStrategy strategy : {PngStrategy::kDefault, PngStrategy::kFast}) {
    const std::string png = EncodePng(image, strategy);
    EXPECT_EQ(EncodePng(image, strategy), png);
    const cv::Mat decoded = cv::imdecode(std::vector<uint8_t>(png.begin(), png.end()), cv::IMREAD_UNCHANGED);
    ASSERT_EQ(decoded.type(), image.type());
    EXPECT_EQ(cv::countNonZero(decoded.reshape(1) != image.reshape(1)), 0);
  }
  EXPECT_NE(EncodePng(image, PngStrategy::kDefault), EncodePng(image, PngStrategy::kFast));
}

// The readers' structure check (png_check.h) passes every PNG the renderer
// writes and refuses a truncated file, a flipped bit and trailing bytes.
TEST(ImageEncode, PngStructureCheckPassesOursAndRefusesDamage) {
  cv::Mat image(40, 60, CV_8UC3, cv::Scalar(10, 120, 230));
  cv::randu(image(cv::Rect(0, 0, 30, 20)), 0, 255);
  for (PngStrategy strategy : {PngStrategy::kDefault, PngStrategy::kFast}) {
    const std::string png = EncodePng(image, strategy);
    EXPECT_NO_THROW(CheckPngStructure(png, "ours.png"));
    std::string flipped = png;
    flipped[png.size() / 2] = static_cast<char>(flipped[png.size() / 2] ^ 0x10);
    for (const auto& [bytes, reason] : {std::pair{png.substr(0, png.size() / 2), "truncated"},
                                        {flipped, "CRC error"},
                                        {png + "x", "1 bytes after IEND"},
                                        {std::string("GIF89a"), "no PNG signature"}}) {
      const std::string message = test::ErrorOf([&] { CheckPngStructure(bytes, "bad.png"); });
      EXPECT_EQ(message.rfind("bad.png: not a whole PNG file (", 0), 0u) << message;
      EXPECT_NE(message.find(reason), std::string::npos) << message;
    }
  }
}

}  // namespace
}  // namespace aar
