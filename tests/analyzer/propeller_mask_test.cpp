// The propeller-disc mask (propeller_mask.h): points on a disc and points
// seen through it are dropped; the rest of the receiver is kept.

#include "aar/analyzer/propeller_mask.h"

#include <gtest/gtest.h>

#include "../test_support.h"
#include "aar/pose.h"
#include "aar/propeller.h"

namespace aar {
namespace {

TEST(PropellerMask, DropsPointsOnAndBehindTheDiscsAndKeepsTheRest) {
  // The receiver 40 m behind and 15 m below a camera at the origin, level.
  Pose pose;
  pose.translation_m = Eigen::Vector3d(-40.0, 0.0, -15.0);
  const Eigen::Isometry3d tanker_from_receiver = IsometryFromPose(pose);
  const Eigen::Vector3d camera(0.0, 0.0, 0.0);
  const Eigen::Vector3d hub = kPropellerHubsInReceiver[0];
  const auto in_tanker = [&](const Eigen::Vector3d& in_receiver) { return tanker_from_receiver * in_receiver; };
  const Eigen::Vector3d on_disc = in_tanker(hub + Eigen::Vector3d(0.02, 0.3, 0.9));
  const Eigen::Vector3d near_disc = in_tanker(hub + Eigen::Vector3d(-0.5, 0.0, -1.2));  // inside the cylinder
  // Behind the disc, on a ray from the camera through the disc's centre.
  const Eigen::Vector3d through = in_tanker(hub) + 0.05 * (in_tanker(hub) - camera);
  const Eigen::Vector3d fuselage = in_tanker(Eigen::Vector3d(0.0, 0.0, 0.8));
  const Eigen::Vector3d wing_tip = in_tanker(Eigen::Vector3d(-0.5, 8.0, 0.0));
  const Eigen::Vector3d beside_disc = in_tanker(hub + Eigen::Vector3d(0.0, 0.0, 1.6));  // beyond the tip circle
  const PropellerMaskOptions options;
  size_t removed = 0;
  const std::vector<Eigen::Vector3d> kept =
      OutsidePropellerDiscs({on_disc, fuselage, near_disc, through, wing_tip, beside_disc}, tanker_from_receiver,
                            camera, options, options.axial_half_width_m, &removed);
  EXPECT_EQ(removed, 3u);
  ASSERT_EQ(kept.size(), 3u);
  EXPECT_TRUE(kept[0].isApprox(fuselage));
  EXPECT_TRUE(kept[1].isApprox(wing_tip));
  EXPECT_TRUE(kept[2].isApprox(beside_disc));
  // A point behind the disc's plane but not behind the disc (its ray misses it) is kept.
  const Eigen::Vector3d behind_but_clear = in_tanker(hub + Eigen::Vector3d(-1.4, -2.6, 0.0));
  EXPECT_EQ(OutsidePropellerDiscs({behind_but_clear}, tanker_from_receiver, camera, options, 0.6).size(), 1u);
}

// A registration from a masked cloud is kept while it leaves the discs in the mask that made it.
TEST(PropellerMask, AgreesWhileTheDiscsStayInTheirMask) {
  Pose pose;
  pose.translation_m = Eigen::Vector3d(-120.0, 1.0, -40.0);
  pose.yaw_deg = 3.0;
  const Eigen::Isometry3d at = IsometryFromPose(pose);
  const auto moved = [&](const Pose& change) { return at * IsometryFromPose(change); };
  Pose along;  // along the axis (the receiver's x)
  along.translation_m.x() = 0.5;
  EXPECT_TRUE(PropellerMaskAgrees(at, moved(along), 0.6));
  EXPECT_FALSE(PropellerMaskAgrees(at, moved(along), 0.4));
  Pose across;  // the hubs 1.3 m down: off the discs' 1.25 m radius
  across.translation_m.z() = -1.3;
  EXPECT_FALSE(PropellerMaskAgrees(at, moved(across), 2.0));
  across.translation_m.z() = -1.0;
  EXPECT_TRUE(PropellerMaskAgrees(at, moved(across), 2.0));
  Pose yawed;  // 10 deg of yaw: the hubs 2.6 m out move 0.45 m along the axis, the rims up to 0.67 m
  yawed.yaw_deg = 10.0;
  EXPECT_TRUE(PropellerMaskAgrees(at, moved(yawed), 2.0));
  EXPECT_FALSE(PropellerMaskAgrees(at, moved(yawed), 0.6));
  Pose flipped;  // a registration that turned the receiver round
  flipped.yaw_deg = 170.0;
  EXPECT_FALSE(PropellerMaskAgrees(at, moved(flipped), 3.0));
}

TEST(PropellerMask, CheckNamesTheInvalidField) {
  PropellerMaskOptions o;
  o.passes = 0;
  EXPECT_EQ(test::ErrorOf([&] { o.Check(); }), "propeller mask: passes must be in [1, 10]");
}

}  // namespace
}  // namespace aar
