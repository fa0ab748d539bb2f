#include "aar/renderer/projection.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <vector>

#include "aar/error.h"
#include "aar/flight_path.h"
#include "aar/pose.h"
#include "aar/renderer/calib_poses.h"
#include "aar/renderer/scene_model.h"
#include "aar/rig.h"

namespace aar {
namespace {

// Framebuffer x of a camera-frame point under ClipFromCamera.
Eigen::Vector2d Framebuffer(const Eigen::Matrix4d& clip_from_cam, const Eigen::Vector3d& p, const Intrinsics& k) {
  const Eigen::Vector4d clip = clip_from_cam * p.homogeneous();
  return {(clip.x() / clip.w() + 1.0) * k.width_px / 2.0, (clip.y() / clip.w() + 1.0) * k.height_px / 2.0};
}

TEST(Projection, MatchesOpenCvPinholeWithHalfPixelOffset) {
  Intrinsics k;
  const Eigen::Vector3d p(1.3, -0.7, 25.0);
  const Eigen::Vector2d uv = *k.Project(p);
  const Eigen::Vector2d fb = Framebuffer(ClipFromCamera(k, 0.5), p, k);
  EXPECT_NEAR(fb.x(), uv.x() + 0.5, 1e-9);
  EXPECT_NEAR(fb.y(), uv.y() + 0.5, 1e-9);
}

TEST(Projection, JitterMovesTheImageOpposite) {
  Intrinsics k;
  const Eigen::Vector3d p(0.2, 0.1, 40.0);
  const Eigen::Vector2d a = Framebuffer(ClipFromCamera(k, 0.5), p, k);
  const Eigen::Vector2d b = Framebuffer(ClipFromCamera(k, 0.5, 0.25, -0.125), p, k);
  EXPECT_NEAR(b.x() - a.x(), -0.25, 1e-9);
  EXPECT_NEAR(b.y() - a.y(), 0.125, 1e-9);
}

TEST(Projection, ReversedDepthIsNearOverZ) {
  Intrinsics k;
  const Eigen::Vector4d clip = ClipFromCamera(k, 0.5) * Eigen::Vector4d(0, 0, 10.0, 1.0);
  EXPECT_NEAR(clip.z() / clip.w(), 0.05, 1e-12);
  EXPECT_NEAR(clip.w(), 10.0, 1e-12);
}

TEST(Projection, InViewFractionCountsPointsInsideTheImage) {
  Camera cam;  // identity pose: camera frame = tanker frame
  const std::vector<Eigen::Vector3d> points = {{0, 0, 10}, {0, 0, -10}, {100, 0, 10}, {0.5, 0.5, 5}};
  EXPECT_DOUBLE_EQ(InViewFraction(points, cam, Eigen::Isometry3d::Identity()), 0.5);
}

TEST(CalibPoses, TwelveBoardPosesFitBothViews) {
  StereoRig rig;
  rig.left.tanker_from_camera.translation() = Eigen::Vector3d(0, 0, 0);
  rig.right.tanker_from_camera.translation() = Eigen::Vector3d(0.5, 0, 0);
  const CalibPoseOptions options;
  const std::vector<Pose> poses = CalibrationBoardPoses(rig, options);
  ASSERT_EQ(poses.size(), 12u);
  for (const Pose& pose : poses) {
    for (const Eigen::Vector3d& corner : BoardOutline(options)) {
      for (const Camera* cam : {&rig.left, &rig.right}) {
        const auto px = cam->intrinsics.Project(cam->tanker_from_camera.inverse() * (IsometryFromPose(pose) * corner));
        ASSERT_TRUE(px.has_value());
        EXPECT_TRUE(cam->intrinsics.Contains(*px));
      }
    }
  }
}

// The corner boards reach the image periphery: each fits both views, their
// outlines come within a few pixels of every image edge, and nearer every
// image corner than the twelve standard poses do.
TEST(CalibPoses, CornerBoardsReachTheImagePeriphery) {
  const StereoRig rig = LoadRig(std::filesystem::path(AAR_SOURCE_DIR) / "scenes" / "rig-distorted.json");
  CalibPoseOptions options;
  options.corner_boards = true;
  const std::vector<Pose> poses = CalibrationBoardPoses(rig, options);
  ASSERT_EQ(poses.size(), 20u);
  const double w = rig.left.intrinsics.width_px - 1.0, h = rig.left.intrinsics.height_px - 1.0;
  const Eigen::Vector2d image_corners[4] = {{0, 0}, {w, 0}, {0, h}, {w, h}};
  // Per image corner, the nearest board outline corner in the left image, of poses [first, last) [px].
  const auto nearest = [&](size_t first, size_t last) {
    std::array<double, 4> d = {1e9, 1e9, 1e9, 1e9};
    for (size_t i = first; i < last; ++i) {
      for (const Eigen::Vector3d& corner : BoardOutline(options)) {
        for (const Camera* cam : {&rig.left, &rig.right}) {
          const auto px =
              cam->intrinsics.Project(cam->tanker_from_camera.inverse() * (IsometryFromPose(poses[i]) * corner));
          EXPECT_TRUE(px.has_value() && px->x() >= options.margin_px - 1e-9 && px->y() >= options.margin_px - 1e-9 &&
                      px->x() <= w - options.margin_px + 1e-9 && px->y() <= h - options.margin_px + 1e-9)
              << "pose " << i;
          if (cam != &rig.left || !px) continue;
          for (int c = 0; c < 4; ++c) d[c] = std::min(d[c], (*px - image_corners[c]).norm());
        }
      }
    }
    return d;
  };
  const std::array<double, 4> standard = nearest(0, 12), periphery = nearest(12, 20);
  for (int c = 0; c < 4; ++c) {
    std::printf("image corner %d: nearest board corner %.0f px (twelve standard poses: %.0f px)\n", c, periphery[c],
                standard[c]);
    EXPECT_LT(periphery[c], 0.6 * standard[c]) << "image corner " << c;
  }
  // Without the option the pose set is unchanged.
  EXPECT_EQ(CalibrationBoardPoses(rig).size(), 12u);
}

TEST(CalibPoses, FarDistancesRepeatTheTwelveTiltsThere) {
  StereoRig rig;
  rig.right.tanker_from_camera.translation() = Eigen::Vector3d(0.5, 0, 0);
  CalibPoseOptions options;
  options.far_distances_m = {30.0, 45.0};
  const std::vector<Pose> poses = CalibrationBoardPoses(rig, options);
  ASSERT_EQ(poses.size(), 36u);
  const std::vector<Pose> near = CalibrationBoardPoses(rig);
  const Eigen::Vector3d centre_in_board((options.board.inner_corners_x - 1) * options.board.square_m / 2.0,
                                        (options.board.inner_corners_y - 1) * options.board.square_m / 2.0, 0.0);
  for (size_t i = 0; i < poses.size(); ++i) {
    const Eigen::Isometry3d left_from_board = rig.left.tanker_from_camera.inverse() * IsometryFromPose(poses[i]);
    // Same tilt as the near set; the board centre at the requested distance.
    EXPECT_TRUE(left_from_board.linear().isApprox(
        (rig.left.tanker_from_camera.inverse() * IsometryFromPose(near[i % 12])).linear(), 1e-12));
    if (i >= 12) {
      EXPECT_NEAR((left_from_board * centre_in_board).z(), i < 24 ? 30.0 : 45.0, 1e-9);
    }
  }
  options.far_distances_m = {5.0};  // nearer than the near set
  EXPECT_THROW(CalibrationBoardPoses(rig, options), Error);
}

}  // namespace
}  // namespace aar

namespace aar {
namespace {

// Issue 9, item 1: on scenes/rig-thesis.json (cameras 41 deg down) the level
// final approach flightpaths/conops-level.csv takes the C-12's T-tail out of
// the top of the frame in region B and brings it back in region C. The same
// InViewFraction the renderer writes into the sidecars, on the receiver model.
TEST(Projection, ThesisRigLevelPathLosesTheTailBetween38And45Metres) {
  const std::filesystem::path source = AAR_SOURCE_DIR;
  const StereoRig rig = LoadRig(source / "scenes" / "rig-thesis.json");
  const std::vector<FlightSample> path = ReadFlightPath(source / "flightpaths" / "conops-level.csv");
  const std::vector<Eigen::Vector3d> points = LoadSceneModel(source / "scenes" / "c12.glb").AllPositions();
  double smallest_38_45 = 1.0, smallest_beyond_45 = 1.0, smallest_below_36 = 1.0;
  for (const FlightSample& s : path) {
    const Eigen::Isometry3d tanker_from_receiver = IsometryFromPose(s.tanker_from_receiver);
    const double range = (tanker_from_receiver.translation() - rig.left.tanker_from_camera.translation()).norm();
    const double in_view = std::min(InViewFraction(points, rig.left, tanker_from_receiver),
                                    InViewFraction(points, rig.right, tanker_from_receiver));
    if (range >= 38.0 && range <= 45.0) {
      smallest_38_45 = std::min(smallest_38_45, in_view);
    } else if (range > 45.0) {
      smallest_beyond_45 = std::min(smallest_beyond_45, in_view);
    } else if (range < 36.0) {
      smallest_below_36 = std::min(smallest_below_36, in_view);
    }
  }
  EXPECT_LT(smallest_38_45, 0.95);            // the tail (and more) leaves the frame
  EXPECT_GT(smallest_38_45, 0.5);             // but most of the receiver stays in view
  EXPECT_DOUBLE_EQ(smallest_beyond_45, 1.0);  // fully in view on the way in
  EXPECT_DOUBLE_EQ(smallest_below_36, 1.0);   // and back in view in region C
}

}  // namespace
}  // namespace aar
