// Where only the propeller blades are (stereo_truth.h, OnPropellerBlade),
// against the committed models: every point of the C-12's airframe is
// outside, the blades' points at any angle are inside from beyond the spinner
// to the tip.

#include "aar/analyzer/stereo_truth.h"

#include <gtest/gtest.h>

#include "../test_support.h"
#include "aar/analyzer/mesh.h"
#include "aar/propeller.h"

namespace aar {
namespace {

TEST(StereoTruth, OnlyTheBladesAreWhereTheBladesAre) {
  const TriangleMesh airframe = LoadReceiverMesh(test::SourcePath("scenes/c12.glb"));
  ASSERT_GT(airframe.vertices.size(), 1000u);
  size_t on = 0;
  for (const Eigen::Vector3d& v : airframe.vertices) on += OnPropellerBlade(v) ? 1 : 0;
  EXPECT_EQ(on, 0u) << "airframe vertices in the blades' volume";

  const TriangleMesh blade = LoadReceiverMesh(test::SourcePath("scenes/c12_propeller.glb"));
  ASSERT_GT(blade.vertices.size(), 100u);
  for (int i = 0; i < 2; ++i) {
    for (double time_s : {0.0, 0.0123, 0.5}) {
      const Eigen::Isometry3d receiver_from_propeller = ReceiverFromPropeller(i, 1700.0, time_s);
      size_t beyond_spinner = 0, inside = 0;
      for (const Eigen::Vector3d& v : blade.vertices) {
        if (std::hypot(v.y(), v.z()) < 0.36) continue;  // the root, inside the spinner and the cowling
        ++beyond_spinner;
        inside += OnPropellerBlade(receiver_from_propeller * v) ? 1 : 0;
      }
      EXPECT_GT(beyond_spinner, 100u);
      EXPECT_EQ(inside, beyond_spinner) << "propeller " << i << " at " << time_s << " s";
    }
  }
  EXPECT_FALSE(OnPropellerBlade(kPropellerHubsInReceiver[0]));                                    // the hub
  EXPECT_FALSE(OnPropellerBlade(kPropellerHubsInReceiver[1] + Eigen::Vector3d(0.0, 0.0, 1.4)));   // beyond the tip
  EXPECT_FALSE(OnPropellerBlade(kPropellerHubsInReceiver[1] + Eigen::Vector3d(-0.2, 0.0, 1.0)));  // behind the disc
  EXPECT_TRUE(OnPropellerBlade(kPropellerHubsInReceiver[1] + Eigen::Vector3d(0.05, 0.7, 0.7)));
}

}  // namespace
}  // namespace aar
