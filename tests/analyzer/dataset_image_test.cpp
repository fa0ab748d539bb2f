#include "aar/analyzer/dataset_image.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <opencv2/imgcodecs.hpp>
#include <random>
#include <string>
#include <vector>

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

}  // namespace
}  // namespace aar
