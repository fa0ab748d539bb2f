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

TEST(PropellerMask, CheckNamesTheInvalidField) {
  PropellerMaskOptions o;
  o.passes = 0;
  EXPECT_EQ(test::ErrorOf([&] { o.Check(); }), "propeller mask: passes must be in [1, 10]");
}

}  // namespace
}  // namespace aar
