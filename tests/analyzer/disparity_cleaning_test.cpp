// Halo removal and the matcher rounding bias.

#include "aar/analyzer/disparity_cleaning.h"

#include <gtest/gtest.h>

#include "aar/analyzer/disparity.h"
#include "aar/analyzer/frame_analysis.h"

namespace aar {
namespace {

constexpr int kInvalid16 = -16;

TEST(HaloRemoval, RemovesTheRingNextToInvalidPixelsAndKeepsTheInterior) {
  // A 40x40 valid square (disparity 10 px) in an invalid (sky) image.
  cv::Mat d(100, 100, CV_16S, cv::Scalar(kInvalid16));
  d(cv::Rect(30, 30, 40, 40)).setTo(cv::Scalar(160));
  HaloRemovalOptions options;
  options.radius_px = 5;
  const size_t removed = RemoveHalo(d, kInvalid16, options);
  EXPECT_EQ(removed, static_cast<size_t>(40 * 40 - 30 * 30));
  EXPECT_EQ(d.at<short>(34, 50), kInvalid16);  // 5 px from the edge: within reach
  EXPECT_EQ(d.at<short>(35, 50), 160);         // 6 px in: kept
  EXPECT_EQ(d.at<short>(50, 50), 160);
}

TEST(HaloRemoval, RemovesBothSidesOfADisparityJump) {
  cv::Mat d(60, 60, CV_16S, cv::Scalar(32));         // background, 2 px
  d(cv::Rect(0, 0, 30, 60)).setTo(cv::Scalar(160));  // foreground, 10 px, on the left
  HaloRemovalOptions options;
  options.radius_px = 3;
  RemoveHalo(d, kInvalid16, options);
  for (int u = 26; u <= 33; ++u) EXPECT_EQ(d.at<short>(30, u), kInvalid16) << u;
  EXPECT_EQ(d.at<short>(30, 25), 160);
  EXPECT_EQ(d.at<short>(30, 34), 32);
}

TEST(HaloRemoval, SmoothSlopesAreNotJumps) {
  cv::Mat d(40, 40, CV_16S);
  for (int v = 0; v < 40; ++v) {
    for (int u = 0; u < 40; ++u) d.at<short>(v, u) = static_cast<short>(100 + u);  // 1/16 px per column
  }
  EXPECT_EQ(RemoveHalo(d, kInvalid16, HaloRemovalOptions{}), 0u);
}

TEST(HaloRemoval, RadiusIsHalfTheBlockPlusThePrefilter) {
  DisparityOptions o;
  o.block_size = 9;
  EXPECT_EQ(HaloRadiusPx(o), 5);
  EXPECT_EQ(FrameAnalysisOptions::ForPreset(Preset::kDefault).halo.radius_px, 5);
  EXPECT_FALSE(FrameAnalysisOptions::ForPreset(Preset::kThesis).remove_halo);
}

TEST(MatcherRounding, FifteenFiveHundredTwelfthsForBlockMatchingOnly) {
  EXPECT_DOUBLE_EQ(MatcherRoundingBiasPx(DisparityAlgorithm::kBlockMatching), 15.0 / 512.0);
  EXPECT_DOUBLE_EQ(MatcherRoundingBiasPx(DisparityAlgorithm::kSemiGlobal), 0.0);
  // The derivation: (d + 15) >> 4 against d / 16 for d spread over a 1/16 px step.
  double sum = 0.0;
  for (int d = 0; d < 4096; ++d) sum += ((d + 15) >> 4) * 16.0 - d;
  EXPECT_DOUBLE_EQ(sum / 4096.0 / 256.0, 15.0 / 512.0);
  EXPECT_TRUE(FrameAnalysisOptions::ForPreset(Preset::kDefault).remove_rounding_bias);
  EXPECT_FALSE(FrameAnalysisOptions::ForPreset(Preset::kThesis).remove_rounding_bias);
}

}  // namespace
}  // namespace aar
