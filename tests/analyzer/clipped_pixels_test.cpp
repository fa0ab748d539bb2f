// Matches over clipped pixels (clipped_pixels.h): their window's reach in
// the left image at the pixel and in the right image at the matched column.

#include "aar/analyzer/clipped_pixels.h"

#include <gtest/gtest.h>

#include "aar/error.h"

namespace aar {
namespace {

constexpr int kInvalid16 = -16;

struct Scene {
  cv::Mat disparity16 = cv::Mat(60, 120, CV_16S, cv::Scalar(10 * 16));  // 10 px everywhere
  cv::Mat left = cv::Mat(60, 120, CV_8U, cv::Scalar(128));
  cv::Mat right = cv::Mat(60, 120, CV_8U, cv::Scalar(128));
};

TEST(ClippedPixels, WithoutClippedPixelsNothingGoes) {
  Scene s;
  s.left.at<unsigned char>(30, 60) = 254;  // bright but not white
  const cv::Mat before = s.disparity16.clone();
  EXPECT_EQ(RemoveClippedMatches(s.disparity16, kInvalid16, s.left, s.right, ClippedPixelOptions{}), 0u);
  EXPECT_EQ(cv::countNonZero(s.disparity16 != before), 0);
}

TEST(ClippedPixels, ALeftClippedPixelTakesTheMatchesWithinReach) {
  Scene s;
  s.left.at<unsigned char>(30, 60) = 255;
  ClippedPixelOptions options;
  options.radius_px = 5;
  EXPECT_EQ(RemoveClippedMatches(s.disparity16, kInvalid16, s.left, s.right, options), 11u * 11u);
  EXPECT_EQ(s.disparity16.at<short>(25, 55), kInvalid16);  // 5 px away both ways: within reach
  EXPECT_EQ(s.disparity16.at<short>(30, 66), 160);         // 6 px away: kept
  EXPECT_EQ(s.disparity16.at<short>(24, 60), 160);
}

TEST(ClippedPixels, ARightClippedPixelTakesTheMatchesThatLandNearIt) {
  Scene s;
  s.right.at<unsigned char>(30, 60) = 255;  // seen by the left pixels at u = 70 (d = 10)
  ClippedPixelOptions options;
  options.radius_px = 2;
  EXPECT_EQ(RemoveClippedMatches(s.disparity16, kInvalid16, s.left, s.right, options), 5u * 5u);
  EXPECT_EQ(s.disparity16.at<short>(30, 70), kInvalid16);
  EXPECT_EQ(s.disparity16.at<short>(32, 72), kInvalid16);
  EXPECT_EQ(s.disparity16.at<short>(30, 60), 160);  // the same column in the left image: its match is elsewhere
  EXPECT_EQ(s.disparity16.at<short>(30, 73), 160);
}

TEST(ClippedPixels, InvalidPixelsStayAndBadInputIsRefused) {
  Scene s;
  s.left.setTo(cv::Scalar(255));
  s.disparity16(cv::Rect(0, 0, 10, 60)).setTo(cv::Scalar(kInvalid16));
  EXPECT_EQ(RemoveClippedMatches(s.disparity16, kInvalid16, s.left, s.right, ClippedPixelOptions{}),
            static_cast<size_t>(110 * 60));
  ClippedPixelOptions bad;
  bad.radius_px = -1;
  EXPECT_THROW(RemoveClippedMatches(s.disparity16, kInvalid16, s.left, s.right, bad), Error);
  cv::Mat colour(60, 120, CV_8UC3, cv::Scalar(0, 0, 0));
  EXPECT_THROW(RemoveClippedMatches(s.disparity16, kInvalid16, colour, s.right, ClippedPixelOptions{}), Error);
}

}  // namespace
}  // namespace aar
