// The ICP seed of tracking mode (--seed previous): the last estimate, not an
// extrapolation, and the centroid again after an implausible estimate.

#include <gtest/gtest.h>

#include "aar/analyzer/frame_analysis.h"
#include "aar/error.h"

namespace aar {
namespace {

Pose PoseAt(double x, double roll, double pitch, double yaw) {
  Pose p;
  p.translation_m = Eigen::Vector3d(x, 0.5, -19.0);
  p.roll_deg = roll;
  p.pitch_deg = pitch;
  p.yaw_deg = yaw;
  return p;
}

TEST(FrameSeed, CentroidSeedIgnoresTheHistory) {
  TrackHistory history;
  history.last = {{1.0, PoseAt(-48.0, 1.0, 2.0, 3.0)}};
  EXPECT_FALSE(SeedFromHistory(history, FrameAnalysisOptions{}).has_value());
}

TEST(FrameSeed, PreviousSeedIsTheLastEstimateNotAnExtrapolation) {
  FrameAnalysisOptions options;
  options.seed = IcpSeed::kPreviousFrame;
  TrackHistory history;
  EXPECT_FALSE(SeedFromHistory(history, options).has_value());  // the first frame: centroid
  history.before_last = {{0.0, PoseAt(-50.0, 0.0, 0.0, 0.0)}};
  history.last = {{1.0, PoseAt(-48.0, 1.0, -2.0, 3.0)}};
  const std::optional<Pose> seed = SeedFromHistory(history, options);
  ASSERT_TRUE(seed.has_value());
  EXPECT_EQ(seed->translation_m.x(), -48.0);  // constant velocity would give -46
  EXPECT_EQ(seed->roll_deg, 1.0);
  EXPECT_EQ(seed->pitch_deg, -2.0);
  EXPECT_EQ(seed->yaw_deg, 3.0);
}

TEST(FrameSeed, AnAttitudeBeyondTheLimitRestartsFromTheCentroid) {
  FrameAnalysisOptions options;
  options.seed = IcpSeed::kPreviousFrame;
  for (const Pose& bad : {PoseAt(-48.0, 15.5, 0.0, 0.0), PoseAt(-48.0, 0.0, -16.0, 0.0), PoseAt(-48.0, 0.0, 0.0, 91.0),
                          PoseAt(-48.0, 0.0, 0.0, -179.0)}) {
    TrackHistory history;
    history.last = {{1.0, bad}};
    EXPECT_FALSE(SeedFromHistory(history, options).has_value())
        << bad.roll_deg << " " << bad.pitch_deg << " " << bad.yaw_deg;
  }
  TrackHistory history;
  history.last = {{1.0, PoseAt(-48.0, 15.0, -15.0, 15.0)}};  // at the limit: kept
  EXPECT_TRUE(SeedFromHistory(history, options).has_value());
  options.max_seed_attitude_deg = -1.0;
  EXPECT_THROW(options.Check(), Error);
}

}  // namespace
}  // namespace aar
