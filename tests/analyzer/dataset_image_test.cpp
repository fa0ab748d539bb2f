#include "aar/analyzer/dataset_image.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <opencv2/imgcodecs.hpp>
#include <random>
#include <string>
#include <vector>

#include "aar/error.h"

namespace aar {
namespace {

std::string Encode(const cv::Mat& image) {
  std::vector<uint8_t> bytes;
  EXPECT_TRUE(cv::imencode(".png", image, bytes));
  return std::string(bytes.begin(), bytes.end());
}

cv::Mat OpenCvDecode(const std::string& bytes, int flags) {
  return cv::imdecode(cv::Mat(1, static_cast<int>(bytes.size()), CV_8U, const_cast<char*>(bytes.data())), flags);
}

cv::Mat Noise(int type, uint32_t seed) {
  cv::Mat image(37, 53, type);
  cv::RNG rng(seed);
  rng.fill(image, cv::RNG::UNIFORM, 0, type == CV_16UC1 ? 65536 : 256);
  return image;
}

TEST(DatasetImage, DecodesEveryKindOfPngAsOpenCvDoes) {
  for (const int type : {CV_8UC1, CV_8UC3, CV_8UC4, CV_16UC1}) {
    const std::string bytes = Encode(Noise(type, static_cast<uint32_t>(type) + 1));
    for (const int flags : {cv::IMREAD_COLOR, cv::IMREAD_UNCHANGED, cv::IMREAD_GRAYSCALE}) {
      const cv::Mat expected = OpenCvDecode(bytes, flags);
      const cv::Mat decoded = DecodeVerifiedPng(bytes, flags);
      ASSERT_EQ(decoded.type(), expected.type()) << "type " << type << " flags " << flags;
      ASSERT_EQ(decoded.size(), expected.size());
      EXPECT_EQ(cv::norm(decoded, expected, cv::NORM_INF), 0.0) << "type " << type << " flags " << flags;
    }
  }
}

TEST(DatasetImage, SkipsTheChecksumsTheHashAlreadyCovers) {
  // The zlib stream's Adler-32 (the last four bytes of the IDAT chunk's data)
  // corrupted: OpenCV refuses the file, the verified decoder does not check it.
  const cv::Mat image = Noise(CV_8UC3, 5);
  std::string bytes = Encode(image);
  const size_t iend = bytes.rfind("IEND");
  ASSERT_NE(iend, std::string::npos);
  const size_t adler = iend - 4 - 4 - 4;  // IEND's length field, then IDAT's CRC, then the Adler-32
  bytes[adler] = static_cast<char>(bytes[adler] ^ 0x5A);
  EXPECT_TRUE(OpenCvDecode(bytes, cv::IMREAD_COLOR).empty());
  const cv::Mat decoded = DecodeVerifiedPng(bytes, cv::IMREAD_COLOR);
  ASSERT_FALSE(decoded.empty());
  EXPECT_EQ(cv::norm(decoded, image, cv::NORM_INF), 0.0);
}

TEST(DatasetImage, BrokenDataDecodesToNothing) {
  std::string bytes = Encode(Noise(CV_8UC3, 9));
  const size_t idat = bytes.find("IDAT");
  ASSERT_NE(idat, std::string::npos);
  for (size_t i = idat + 6; i < idat + 40; ++i) bytes[i] = static_cast<char>(0xFF);
  EXPECT_TRUE(DecodeVerifiedPng(bytes, cv::IMREAD_COLOR).empty());
  EXPECT_TRUE(DecodeVerifiedPng("not a png", cv::IMREAD_COLOR).empty());
}

// A thermal pair: one window for both images, the pair's coldest count to
// 0 and hottest to 255, so that a temperature reads the same in both; a
// visible image is refused with its file named.
TEST(DatasetImage, AThermalPairIsWindowedAsOne) {
  cv::Mat left(2, 2, CV_16UC1), right(2, 2, CV_16UC1);
  left.at<uint16_t>(0, 0) = 22000;  // 220 K, the pair's coldest
  left.at<uint16_t>(0, 1) = 24700;
  left.at<uint16_t>(1, 0) = 24700;
  left.at<uint16_t>(1, 1) = 25350;
  right.setTo(24700);
  right.at<uint16_t>(1, 1) = 28400;  // the hottest, in the other image
  WindowThermalPair(left, right, "l.png");
  ASSERT_EQ(left.type(), CV_8UC3);
  ASSERT_EQ(right.type(), CV_8UC3);
  const auto grey = [](const cv::Mat& m, int y, int x) { return int(m.at<cv::Vec3b>(y, x)[0]); };
  EXPECT_EQ(grey(left, 0, 0), 0);
  EXPECT_EQ(grey(right, 1, 1), 255);
  EXPECT_EQ(grey(left, 0, 1), grey(right, 0, 0));  // 247 K in both
  EXPECT_EQ(grey(left, 0, 1), int(std::lround(2700.0 * 255.0 / 6400.0)));
  EXPECT_EQ(grey(left, 1, 1), int(std::lround(3350.0 * 255.0 / 6400.0)));
  cv::Mat colour(2, 2, CV_8UC3, cv::Scalar(1, 2, 3)), other(2, 2, CV_16UC1, cv::Scalar(1));
  try {
    WindowThermalPair(colour, other, "l.png");
    FAIL() << "an 8-bit image was windowed";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("l.png: the rig declares an LWIR camera"), std::string::npos);
  }
}

}  // namespace
}  // namespace aar
