#include "aar/pose.h"

#include <gtest/gtest.h>

#include "aar/region.h"

namespace aar {
namespace {

TEST(Pose, RoundTripThroughIsometry) {
  Pose pose;
  pose.translation_m = {-47.7, 1.5, -18.9};
  pose.roll_deg = 3.0;
  pose.pitch_deg = -2.5;
  pose.yaw_deg = 170.0;
  const Pose back = PoseFromIsometry(IsometryFromPose(pose));
  EXPECT_NEAR((back.translation_m - pose.translation_m).norm(), 0.0, 1e-12);
  EXPECT_NEAR(back.roll_deg, 3.0, 1e-9);
  EXPECT_NEAR(back.pitch_deg, -2.5, 1e-9);
  EXPECT_NEAR(back.yaw_deg, 170.0, 1e-9);
}

TEST(Pose, RightHandRuleDirections) {
  // Positive pitch moves the nose (+x) down, positive yaw moves it left (+y).
  const Eigen::Vector3d nose = Eigen::Vector3d::UnitX();
  EXPECT_LT((RotationFromRollPitchYaw(0, 10, 0) * nose).z(), 0.0);
  EXPECT_GT((RotationFromRollPitchYaw(0, 0, 10) * nose).y(), 0.0);
  EXPECT_GT((RotationFromRollPitchYaw(10, 0, 0) * Eigen::Vector3d::UnitY()).z(), 0.0);
}

TEST(Pose, WrapDegreesIntoHalfOpenInterval) {
  EXPECT_DOUBLE_EQ(WrapDegrees(180.0), 180.0);
  EXPECT_DOUBLE_EQ(WrapDegrees(-180.0), 180.0);
  EXPECT_DOUBLE_EQ(WrapDegrees(190.0), -170.0);
  EXPECT_DOUBLE_EQ(WrapDegrees(-370.0), -10.0);
}

TEST(Pose, BodyFromGltfIsProperRotation) {
  const Eigen::Matrix3d m = BodyFromGltf();
  EXPECT_NEAR(m.determinant(), 1.0, 1e-12);
  EXPECT_EQ(m * Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitX());  // glTF forward is body x
  EXPECT_EQ(m * Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitZ());  // glTF up is body z
}

TEST(Region, BoundariesFollowThesis) {
  EXPECT_EQ(RegionForRange(31.9), "none");
  EXPECT_EQ(RegionForRange(32.0), "C");
  EXPECT_EQ(RegionForRange(38.0), "B");
  EXPECT_EQ(RegionForRange(70.0), "A");
  EXPECT_EQ(RegionForRange(175.0), "A");
  EXPECT_EQ(RegionForRange(175.1), "none");
  EXPECT_EQ(RangeBinForRange(59.9), "20-60");
  EXPECT_EQ(RangeBinForRange(110.0), "60-110");
}

}  // namespace
}  // namespace aar
