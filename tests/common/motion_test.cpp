// What moves during an exposure: the receiver between flight-path samples
// (flight_path.h, TankerFromReceiverAt) and its propellers (propeller.h).

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "../test_support.h"
#include "aar/flight_path.h"
#include "aar/pose.h"
#include "aar/propeller.h"

namespace aar {
namespace {

using test::ErrorOf;

FlightSample Sample(double t, double x, double yaw_deg) {
  FlightSample s;
  s.time_s = t;
  s.tanker_from_receiver.translation_m = Eigen::Vector3d(x, 1.0, -20.0);
  s.tanker_from_receiver.yaw_deg = yaw_deg;
  return s;
}

TEST(Motion, ReceiverPoseIsTheSampleAtItsTimeAndInterpolatedBetween) {
  const std::vector<FlightSample> path = {Sample(0.0, -60.0, 0.0), Sample(0.5, -59.0, 10.0), Sample(1.0, -57.0, 10.0)};
  for (const FlightSample& s : path) {
    EXPECT_TRUE(TankerFromReceiverAt(path, s.time_s).isApprox(IsometryFromPose(s.tanker_from_receiver), 1e-12));
  }
  // A quarter of the way through the first interval: constant velocity and yaw rate.
  const Pose quarter = PoseFromIsometry(TankerFromReceiverAt(path, 0.125));
  EXPECT_NEAR(quarter.translation_m.x(), -59.75, 1e-12);
  EXPECT_NEAR(quarter.yaw_deg, 2.5, 1e-9);
  // Past the last sample: the last interval's velocity goes on (2 m per 0.5 s).
  EXPECT_NEAR(TankerFromReceiverAt(path, 1.002).translation().x(), -57.0 + 0.008, 1e-12);
  // Before the first: the first interval's, backwards.
  EXPECT_NEAR(PoseFromIsometry(TankerFromReceiverAt(path, -0.05)).yaw_deg, -1.0, 1e-9);
  // One sample: no motion.
  EXPECT_TRUE(TankerFromReceiverAt({path[1]}, 7.0).isApprox(IsometryFromPose(path[1].tanker_from_receiver), 1e-15));
}

TEST(Motion, TimesThatDoNotIncreaseAreRefusedNamingTheSamples) {
  const std::vector<FlightSample> path = {Sample(0.0, -60.0, 0.0), Sample(0.5, -59.0, 0.0), Sample(0.5, -58.0, 0.0)};
  EXPECT_EQ(ErrorOf([&] { CheckTimesIncrease(path, "p.csv"); }),
            "p.csv: time_s must increase from sample to sample, but sample 2 (0.500 s) follows sample 1 (0.500 s)");
  EXPECT_EQ(ErrorOf([&] { CheckTimesIncrease({path[0], path[1]}, "p.csv"); }), "");
}

TEST(Motion, PropellersTurnClockwiseFromBehindAtTheirSpeed) {
  // 60 rpm: a turn a second; a quarter second is a quarter turn after the phase.
  EXPECT_NEAR(PropellerAngleDeg(0, 60.0, 0.25), kPropellerPhaseDeg[0] + 90.0, 1e-9);
  EXPECT_NEAR(PropellerAngleDeg(1, 60.0, 0.25), kPropellerPhaseDeg[1] + 90.0, 1e-9);
  // Whole turns drop out before scaling: an hour later, the same angle to 1e-6 deg.
  EXPECT_NEAR(PropellerAngleDeg(0, 1700.0, 3600.0 + 0.001), PropellerAngleDeg(0, 1700.0, 0.001), 1e-6);
  EXPECT_GE(PropellerAngleDeg(0, 1700.0, 1234.567), 0.0);
  EXPECT_LT(PropellerAngleDeg(0, 1700.0, 1234.567), 360.0);
  // Blade 0 starts along +z; a positive turn about +x (clockwise seen from
  // behind, looking forward) moves it towards -y, about the hub.
  const double quarter_turn_s = 0.25 * 60.0 / 1700.0;
  const Eigen::Vector3d tip = ReceiverFromPropeller(0, 1700.0, quarter_turn_s) * Eigen::Vector3d(0, 0, 1.25);
  EXPECT_TRUE(tip.isApprox(kPropellerHubsInReceiver[0] + Eigen::Vector3d(0, -1.25, 0), 1e-9));
  EXPECT_GT(kPropellerHubsInReceiver[0].y(), 0.0);  // the left engine
  EXPECT_EQ(kPropellerHubsInReceiver[1].y(), -kPropellerHubsInReceiver[0].y());
}

}  // namespace
}  // namespace aar
