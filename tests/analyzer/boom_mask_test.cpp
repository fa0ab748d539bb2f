// Drawing the boom into the rectified images from its angles and the rig
// (analyzer/include/aar/analyzer/boom_mask.h), removing the disparities on
// it, and the receiver fraction it hides.

#include "aar/analyzer/boom_mask.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "aar/analyzer/mesh.h"
#include "aar/dataset.h"
#include "aar/error.h"
#include "aar/rig.h"
#include "aar/stereo_calibration.h"

namespace aar {
namespace {

const std::filesystem::path kSource = AAR_SOURCE_DIR;

struct Fixture {
  StereoRig rig = LoadRig(kSource / "scenes" / "rig.json");
  StereoCalibration calibration = IdealCalibration(rig);  // R1 = I: the rectified left camera is the left camera
  BoomMasker masker{LoadReceiverMesh(kSource / "scenes" / "kc46_boom.glb"),
                    LoadReceiverMesh(kSource / "scenes" / "kc46_boom_tube.glb"), calibration,
                    rig.left.tanker_from_camera};

  // The rectified pixel of a tanker point in the left (or right) image.
  cv::Point Pixel(const Eigen::Vector3d& point_in_tanker, bool right) const {
    const Eigen::Vector3d p = rig.left.tanker_from_camera.inverse() * point_in_tanker;
    const double f = calibration.P1.at<double>(0, 0);
    const double tx = right ? calibration.P2.at<double>(0, 3) : 0.0;
    return {static_cast<int>(std::lround((f * p.x() + tx) / p.z() + calibration.P1.at<double>(0, 2))),
            static_cast<int>(std::lround(f * p.y() / p.z() + calibration.P1.at<double>(1, 2)))};
  }
};

TEST(BoomMask, StowedBoomIsOutOfViewAndLoweredBoomCoversItsAxis) {
  const Fixture fx;
  const BoomMasks stowed = fx.masker.Draw(BoomPose{});
  EXPECT_EQ(cv::countNonZero(stowed.left), 0);
  EXPECT_EQ(cv::countNonZero(stowed.right), 0);

  const BoomPose lowered{35.0, 3.0, 4.0};
  const BoomMasks masks = fx.masker.Draw(lowered);
  EXPECT_GT(cv::countNonZero(masks.left), 1000);
  // Points on the boom's axis (outer tube at 9 m, nozzle ball at 13 m from the hinge) are covered in both images.
  const Eigen::Isometry3d tanker_from_boom = TankerFromBoom(lowered);
  const Eigen::Isometry3d tanker_from_tube = TankerFromBoomTube(lowered);
  for (const Eigen::Vector3d& p : {Eigen::Vector3d(tanker_from_boom * Eigen::Vector3d(-9.0, 0, 0)),
                                   Eigen::Vector3d(tanker_from_tube * Eigen::Vector3d(-13.0, 0, 0))}) {
    for (const bool right : {false, true}) {
      const cv::Point pixel = fx.Pixel(p, right);
      ASSERT_TRUE(cv::Rect(0, 0, 1024, 768).contains(pixel)) << pixel;
      EXPECT_EQ((right ? masks.right : masks.left)(pixel), 255) << pixel << (right ? " right" : " left");
    }
  }
  // The receiver's reference point at the contact position, below the boom's line, stays clear.
  const cv::Point contact = fx.Pixel(fx.rig.contact_position_m, false);
  EXPECT_EQ(masks.left(contact), 0) << contact;
}

TEST(BoomMask, MarginGrowsTheMask) {
  const Fixture fx;
  BoomMaskOptions none;
  none.margin_px = 0;
  const BoomMasker tight(LoadReceiverMesh(kSource / "scenes" / "kc46_boom.glb"),
                         LoadReceiverMesh(kSource / "scenes" / "kc46_boom_tube.glb"), fx.calibration,
                         fx.rig.left.tanker_from_camera, none);
  const BoomPose pose{35.0, 0.0, 6.0};
  EXPECT_GT(cv::countNonZero(fx.masker.Draw(pose).left), cv::countNonZero(tight.Draw(pose).left) + 1000);
  BoomMaskOptions bad;
  bad.margin_px = -1;
  EXPECT_THROW(bad.Check(), Error);
}

TEST(BoomMask, RemovesDisparitiesOnTheBoomOrMatchedOntoIt) {
  BoomMasks masks{cv::Mat1b::zeros(20, 40), cv::Mat1b::zeros(20, 40)};
  masks.left(5, 10) = 255;   // the left pixel (10, 5) is on the boom
  masks.right(7, 20) = 255;  // its match for the left pixel (24, 7) at disparity 4 is on the boom
  // A region of the rectified left image starting at (2, 3), every disparity 4 px.
  cv::Mat disparity16(10, 30, CV_16S, cv::Scalar(4 * 16));
  disparity16.at<int16_t>(0, 0) = -16;  // already invalid: not counted
  const size_t removed = BoomMasker::RemoveDisparities(disparity16, -16, cv::Point(2, 3), masks);
  EXPECT_EQ(removed, 2u);
  EXPECT_EQ(disparity16.at<int16_t>(5 - 3, 10 - 2), -16);
  EXPECT_EQ(disparity16.at<int16_t>(7 - 3, 24 - 2), -16);
  EXPECT_EQ(disparity16.at<int16_t>(7 - 3, 20 - 2), 4 * 16);  // a left pixel whose own position is on the right mask
  EXPECT_EQ(cv::countNonZero(disparity16 == -16), 3);
}

TEST(BoomMask, ReceiverOccludedFractionCountsBoomIdsInTheSilhouette) {
  cv::Mat1b ids = cv::Mat1b::zeros(4, 4), silhouette = cv::Mat1b::zeros(4, 4);
  silhouette(cv::Rect(0, 0, 4, 2)) = 255;  // 8 receiver pixels
  ids(cv::Rect(0, 0, 4, 2)) = 1;
  ids(0, 0) = ids(1, 3) = kBoomMaskId;  // two of them hidden by the boom
  ids(3, 3) = kBoomMaskId;              // the boom outside the receiver: not counted
  EXPECT_DOUBLE_EQ(ReceiverOccludedFraction(ids, silhouette), 0.25);
  EXPECT_DOUBLE_EQ(ReceiverOccludedFraction(ids, cv::Mat1b::zeros(4, 4)), 0.0);
  EXPECT_THROW(ReceiverOccludedFraction(ids, cv::Mat1b::zeros(3, 4)), Error);
}

}  // namespace
}  // namespace aar
