// BOP's Visible Surface Discrepancy against hand-computed cases: a box seen
// face-on whose silhouette covers whole pixels, moved sideways, moved away
// and partly hidden by an occluder (vsd.h); its scores (bop_metrics.h).

#include "aar/analyzer/vsd.h"

#include <gtest/gtest.h>

#include <cmath>

#include "aar/analyzer/bop_metrics.h"
#include "aar/analyzer/frame_results.h"
#include "aar/error.h"
#include "test_meshes.h"

namespace aar {
namespace {

// A 2 x 1 x 1 m box whose near face is 10 m in front of a 40 x 30 px camera
// with a focal length of 100 px: the face spans u in [9.5, 29.5] and v in
// [9.5, 19.5], so it covers the 20 x 10 pixels with centres at u = 10..29,
// v = 10..19 exactly; its sides hide behind it.
struct FaceOnBox {
  TriangleMesh mesh;
  Intrinsics camera;
  Eigen::Isometry3d cam_from_model_truth = Eigen::Isometry3d::Identity();
  double diameter_m = std::sqrt(6.0);
  FaceOnBox() {
    test::AddBox(mesh, Eigen::Vector3d::Zero(), Eigen::Vector3d(1.0, 0.5, 0.5));
    camera.width_px = 40;
    camera.height_px = 30;
    camera.fx_px = camera.fy_px = 100.0;
    camera.cx_px = 19.5;
    camera.cy_px = 14.5;
    cam_from_model_truth.translation() = Eigen::Vector3d(0.0, 0.0, 10.5);
  }
  DepthBuffer Render(const Eigen::Isometry3d& cam_from_model) const {
    return RasterizeDepth(mesh, camera, cam_from_model, 0.1);
  }
  // The test image: the box at the truth, 0 (nothing measured) elsewhere.
  cv::Mat TestDepth() const {
    const DepthBuffer truth = Render(cam_from_model_truth);
    cv::Mat depth(camera.height_px, camera.width_px, CV_32F);
    for (int y = 0; y < depth.rows; ++y)
      for (int x = 0; x < depth.cols; ++x) depth.at<float>(y, x) = std::isfinite(truth.At(x, y)) ? truth.At(x, y) : 0.f;
    return depth;
  }
  VsdErrors Vsd(const Eigen::Isometry3d& estimate, const cv::Mat& test) const {
    return ComputeVsd(mesh, camera, estimate, cam_from_model_truth, test, diameter_m, 0.1);
  }
  Eigen::Isometry3d Moved(const Eigen::Vector3d& by) const {
    Eigen::Isometry3d moved = cam_from_model_truth;
    moved.translation() += by;
    return moved;
  }
};

void ExpectAll(const VsdErrors& errors, double value) {
  for (double e : errors) EXPECT_NEAR(e, value, 1e-12);
}

TEST(Vsd, TheTruthItselfHasNoDiscrepancy) {
  const FaceOnBox box;
  size_t covered = 0;
  const DepthBuffer truth = box.Render(box.cam_from_model_truth);
  for (float d : truth.depth_m) covered += std::isfinite(d) ? 1 : 0;
  ASSERT_EQ(covered, 200u);  // the face covers whole pixels, as the cases below assume
  ExpectAll(box.Vsd(box.cam_from_model_truth, box.TestDepth()), 0.0);
}

TEST(Vsd, ASidewaysShiftCostsThePixelsOutsideTheOverlap) {
  // 0.2 m at 10 m is 2 px: the estimate covers u = 12..31. Both are visible
  // (nothing was measured beside the box), they overlap on 18 x 10 pixels at
  // the same distance, and 2 x 2 x 10 pixels are in one only: e = 40 / 220
  // at every tau.
  const FaceOnBox box;
  ExpectAll(box.Vsd(box.Moved({0.2, 0.0, 0.0}), box.TestDepth()), 40.0 / 220.0);
}

TEST(Vsd, ADepthErrorCountsBelowTheToleranceOnly) {
  // 0.12 diameters farther: the near face still covers the same 200 pixels
  // (half-width 100 / 10.29 > 9.5 px), the estimate is visible through the
  // truth's visibility, and every overlap pixel is off by 0.12-0.1207
  // diameters (ray lengths 1 to 1.0055): misaligned for tau 0.05 and 0.10,
  // aligned from 0.15 on.
  const FaceOnBox box;
  const VsdErrors e = box.Vsd(box.Moved({0.0, 0.0, 0.12 * box.diameter_m}), box.TestDepth());
  EXPECT_EQ(e[0], 1.0);
  EXPECT_EQ(e[1], 1.0);
  for (size_t t = 2; t < e.size(); ++t) EXPECT_EQ(e[t], 0.0) << t;
}

TEST(Vsd, AnOccluderHidesWhatTheTestImageDoesNotShow) {
  // Something 5 m from the camera covers u = 10..19: the truth's visible part
  // is u = 20..29. The estimate shifted by 2 px is visible at u = 20..31 (its
  // u = 12..19 are behind the occluder): e = 20 / 120 (without the occluder
  // 40 / 220). An estimate at the truth has no discrepancy, and a test image
  // that hides the whole box gives 1 (an empty union).
  const FaceOnBox box;
  cv::Mat test = box.TestDepth();
  test.colRange(10, 20).setTo(5.0f);
  ExpectAll(box.Vsd(box.cam_from_model_truth, test), 0.0);
  ExpectAll(box.Vsd(box.Moved({0.2, 0.0, 0.0}), test), 20.0 / 120.0);
  ExpectAll(box.Vsd(box.Moved({0.2, 0.0, 0.0}), cv::Mat(30, 40, CV_32F, cv::Scalar(1.0f))), 1.0);
}

TEST(Vsd, RefusesImagesOfAnotherSize) {
  const FaceOnBox box;
  EXPECT_THROW(box.Vsd(box.cam_from_model_truth, cv::Mat(30, 41, CV_32F, cv::Scalar(0.0f))), Error);
  EXPECT_THROW(box.Vsd(box.cam_from_model_truth, cv::Mat(30, 40, CV_64F, cv::Scalar(0.0))), Error);
}

TEST(Vsd, ScoresAverageTheRecallOverTausAndThresholds) {
  // e_VSD 0 at the first five tau (correct at all 10 thresholds), 0.12 at the
  // next four (correct at 0.15..0.50: 8) and 1 at the last (never): the
  // estimate's mean recall is (5 x 10 + 4 x 8) / 100 = 0.82; with a frame
  // without an estimate, AR_VSD = 0.41, and AR = (0.41 + 0.4 + 0.45) / 3 with
  // ScoresAverageTheRecallOverBopsThresholds's MSSD and MSPD.
  PoseErrorMetrics e{0.12, 12.0, 0.05, 0.2, VsdErrors{0, 0, 0, 0, 0, 0.12, 0.12, 0.12, 0.12, 1.0}};
  const BopScores s = ScoreBop({e, std::nullopt}, BopScale{1.0, 1280});
  ASSERT_TRUE(s.ar_vsd.has_value());
  EXPECT_NEAR(*s.ar_vsd, 0.41, 1e-12);
  EXPECT_NEAR(*s.ar, (0.41 + 0.4 + 0.45) / 3.0, 1e-12);
  e.vsd.reset();
  EXPECT_FALSE(ScoreBop({e}, BopScale{1.0, 1280}).ar_vsd.has_value());
}

TEST(Vsd, FrameResultsCarryTheErrorsThroughTheCsv) {
  FrameResult f;
  f.frame = 3;
  f.bop_errors = PoseErrorMetrics{0.25, 3.5, 0.125, 0.0625, VsdErrors{1, 0.5, 0.25, 0.125, 0, 0, 0, 0, 0, 0}};
  const std::string text = FormatFrameResults({f});
  const std::vector<FrameResult> back = ParseFrameResults(text, "test");
  ASSERT_TRUE(back[0].bop_errors && back[0].bop_errors->vsd);
  EXPECT_EQ(*back[0].bop_errors->vsd, *f.bop_errors->vsd);
  std::string short_list = text;
  short_list.replace(short_list.find("1.000000 0.500000"), 9, "");
  EXPECT_THROW(ParseFrameResults(short_list, "test"), Error);
}

}  // namespace
}  // namespace aar
