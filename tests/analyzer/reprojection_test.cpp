#include "aar/analyzer/reprojection.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "aar/analyzer/subpixel.h"
#include "aar/error.h"
#include "aar/pose.h"
#include "aar/rig.h"
#include "aar/stereo_calibration.h"

namespace aar {
namespace {

// The thesis's plain re-projection (no disparity offset): the geometry tests
// check equation 1 exactly.
ReprojectionOptions PlainOptions() {
  ReprojectionOptions options;
  options.disparity_offset_px = 0.0;
  return options;
}

StereoRig TestRig() { return LoadRig(std::filesystem::path(AAR_SOURCE_DIR) / "scenes" / "rig.json"); }

constexpr int kInvalid16 = -16;  // (min_disparity - 1) * 16 with min_disparity 0

// A small image keeps the tests fast; the rig's intrinsics still apply.
constexpr int kWidth = 160;
constexpr int kHeight = 120;

TEST(Reprojection, ConstantDisparityPlaneLandsAtFocalTimesBaselineOverDisparity) {
  const StereoRig rig = TestRig();
  const StereoCalibration c = IdealCalibration(rig);
  const Eigen::Isometry3d tanker_from_left = rig.left.tanker_from_camera;
  const double f = rig.left.intrinsics.fx_px, b = rig.Baseline();
  const double cx = rig.left.intrinsics.cx_px, cy = rig.left.intrinsics.cy_px;
  const short d16 = 200;  // 12.5 px
  const cv::Mat disparity(kHeight, kWidth, CV_16S, cv::Scalar(d16));
  ReprojectionOptions options = PlainOptions();
  const SensedCloud cloud = Reproject(disparity, kInvalid16, c, tanker_from_left, options);

  const size_t n = static_cast<size_t>(kWidth) * kHeight;
  EXPECT_EQ(cloud.valid_count, n);
  ASSERT_EQ(cloud.kept_count, (n + 7) / 8);
  ASSERT_EQ(cloud.points_in_tanker.size(), cloud.kept_count);
  const double z = f * b / 12.5;  // 36 m
  const Eigen::Isometry3d left_from_tanker = tanker_from_left.inverse();
  for (size_t k = 0; k < cloud.kept_count; ++k) {
    const size_t pixel = 8 * k;  // every valid: kept k is the (8k)-th pixel in row-major order
    const double u = static_cast<double>(pixel % kWidth), v = static_cast<double>(pixel / kWidth);
    const Eigen::Vector3d expected_in_left((u - cx) * z / f, (v - cy) * z / f, z);
    const Eigen::Vector3d point_in_left = left_from_tanker * cloud.points_in_tanker[k];
    ASSERT_LT((point_in_left - expected_in_left).norm(), 1e-9) << "kept point " << k;
  }
}

TEST(Reprojection, SlantedPlaneStaysOnItsPlaneInTheTankerFrame) {
  const StereoRig rig = TestRig();
  const StereoCalibration c = IdealCalibration(rig);
  const Eigen::Isometry3d tanker_from_left = rig.left.tanker_from_camera;
  const double f = rig.left.intrinsics.fx_px, b = rig.Baseline();
  const double cx = rig.left.intrinsics.cx_px, cy = rig.left.intrinsics.cy_px;
  // d = a u + bb v + c0, quantized to 1/16 px; the quantized d is what must be honoured.
  const double a = 0.02, bb = -0.015, c0 = 6.0;
  cv::Mat disparity(kHeight, kWidth, CV_16S);
  for (int v = 0; v < kHeight; ++v) {
    for (int u = 0; u < kWidth; ++u)
      disparity.at<short>(v, u) = static_cast<short>(std::lround(16 * (a * u + bb * v + c0)));
  }
  ReprojectionOptions options = PlainOptions();
  options.keep_one_in = 1;
  const SensedCloud cloud = Reproject(disparity, kInvalid16, c, tanker_from_left, options);
  ASSERT_EQ(cloud.kept_count, static_cast<size_t>(kWidth) * kHeight);
  const Eigen::Isometry3d left_from_tanker = tanker_from_left.inverse();
  for (size_t k = 0; k < cloud.kept_count; ++k) {
    const int u = static_cast<int>(k % kWidth), v = static_cast<int>(k / kWidth);
    const double d = disparity.at<short>(v, u) / 16.0;
    const Eigen::Vector3d p = left_from_tanker * cloud.points_in_tanker[k];
    // Depth f b / d and the pixel's ray: p = z ((u - cx) / f, (v - cy) / f, 1).
    const double z = f * b / d;
    ASSERT_NEAR(p.z(), z, 1e-9 * z);
    ASSERT_NEAR(p.x(), (u - cx) * z / f, 1e-9 * z);
    ASSERT_NEAR(p.y(), (v - cy) * z / f, 1e-9 * z);
  }
}

TEST(Reprojection, DropsInvalidBehindAndBeyondMaxDepthThenKeepsOneInEight) {
  const StereoRig rig = TestRig();
  const StereoCalibration c = IdealCalibration(rig);
  const double fb = rig.left.intrinsics.fx_px * rig.Baseline();  // 450 px m
  cv::Mat disparity(kHeight, kWidth, CV_16S, cv::Scalar(160));   // 10 px -> 45 m
  size_t expected_valid = static_cast<size_t>(kWidth) * kHeight;
  auto set = [&](int v, int u, short value) {
    disparity.at<short>(v, u) = value;
    --expected_valid;
  };
  for (int u = 0; u < kWidth; u += 3) set(0, u, kInvalid16);             // invalid marker
  for (int u = 1; u < kWidth; u += 3) set(1, u, -8);                     // negative: behind the camera
  for (int u = 2; u < kWidth; u += 3) set(2, u, 0);                      // zero: at infinity (W = 0)
  const short beyond = static_cast<short>(std::floor(16 * fb / 750.0));  // depth > 750 m
  ASSERT_GT(fb / (beyond / 16.0), 750.0);
  for (int u = 0; u < kWidth; u += 2) set(3, u, beyond);
  const short at_limit = static_cast<short>(std::ceil(16 * fb / 750.0));  // depth just under 750 m: kept
  ASSERT_LE(fb / (at_limit / 16.0), 750.0);
  disparity.at<short>(4, 0) = at_limit;

  const SensedCloud cloud = Reproject(disparity, kInvalid16, c, Eigen::Isometry3d::Identity(), PlainOptions());
  EXPECT_EQ(cloud.valid_count, expected_valid);
  EXPECT_EQ(cloud.kept_count, (expected_valid + 7) / 8);
  for (const Eigen::Vector3d& p : cloud.points_in_tanker) {
    ASSERT_GT(p.z(), 0.0);
    ASSERT_LE(p.z(), 750.0);
  }
  ReprojectionOptions keep_all = PlainOptions();
  keep_all.keep_one_in = 1;
  const SensedCloud all = Reproject(disparity, kInvalid16, c, Eigen::Isometry3d::Identity(), keep_all);
  ASSERT_EQ(all.kept_count, expected_valid);
  for (size_t k = 0; k < cloud.kept_count; ++k) ASSERT_EQ(cloud.points_in_tanker[k], all.points_in_tanker[8 * k]);
  ReprojectionOptions bad;
  bad.keep_one_in = 0;
  EXPECT_THROW(Reproject(disparity, kInvalid16, c, Eigen::Isometry3d::Identity(), bad), Error);
}

// A receiver patch in front of a textured background whose valid disparities
// lie beyond max_depth_m (terrain at kilometres): the target_points step
// counts only the patch, so it keeps about target_points points.
TEST(Reprojection, TargetPointsStepIgnoresBackgroundBeyondMaxDepth) {
  const StereoRig rig = TestRig();
  const StereoCalibration c = IdealCalibration(rig);
  cv::Mat disparity(kHeight, kWidth, CV_16S, cv::Scalar(4));   // 0.25 px: 1.8 km, beyond 750 m
  disparity(cv::Rect(40, 30, 80, 60)).setTo(cv::Scalar(200));  // 12.5 px: 36 m, 4,800 pixels
  ReprojectionOptions options = PlainOptions();
  options.keep_one_in = 1;
  options.target_points = 1200;
  const SensedCloud cloud = Reproject(disparity, kInvalid16, c, rig.left.tanker_from_camera, options);
  EXPECT_EQ(cloud.valid_count, 4800u);
  EXPECT_EQ(cloud.kept_count, 1200u);  // step 4800 / 1200 = 4, not 19200 / 1200 = 16
}

// The median gate: a receiver patch at 36 m and wrong background matches at
// 300 m (1.5 px): with max_depth_over_median 1.5 only the patch is kept.
TEST(Reprojection, MedianDepthGateDropsFarWrongMatches) {
  const StereoRig rig = TestRig();
  const StereoCalibration c = IdealCalibration(rig);
  cv::Mat disparity(kHeight, kWidth, CV_16S, cv::Scalar(kInvalid16));
  disparity(cv::Rect(40, 30, 80, 60)).setTo(cv::Scalar(200));  // 12.5 px: 36 m, 4,800 pixels
  disparity(cv::Rect(0, 0, 30, 30)).setTo(cv::Scalar(24));     // 1.5 px: 300 m, 900 pixels
  ReprojectionOptions options = PlainOptions();
  options.keep_one_in = 1;
  EXPECT_EQ(Reproject(disparity, kInvalid16, c, rig.left.tanker_from_camera, options).kept_count, 5700u);
  options.max_depth_over_median = 1.5;
  const SensedCloud cloud = Reproject(disparity, kInvalid16, c, rig.left.tanker_from_camera, options);
  EXPECT_EQ(cloud.kept_count, 4800u);
  for (const Eigen::Vector3d& pixel : cloud.pixels) EXPECT_EQ(pixel.z(), 12.5);
}

TEST(Reprojection, MatchesReprojectImageTo3DAndUndoesRectification) {
  // A calibration with a rotated rectification: point_in_left = R1^T point_in_rect_left.
  StereoCalibration c = IdealCalibration(TestRig());
  const Eigen::Matrix3d r1 = RotationFromRollPitchYaw(2.0, -3.0, 1.5);
  c.R1 = (cv::Mat_<double>(3, 3) << r1(0, 0), r1(0, 1), r1(0, 2), r1(1, 0), r1(1, 1), r1(1, 2), r1(2, 0), r1(2, 1),
          r1(2, 2));
  c.Q.at<double>(0, 3) = -500.25;  // off-centre principal point, non-square-ish Q
  cv::Mat disparity(kHeight, kWidth, CV_16S);
  cv::RNG rng(7);
  rng.fill(disparity, cv::RNG::UNIFORM, 16, 16 * 40);
  ReprojectionOptions options = PlainOptions();
  options.keep_one_in = 1;
  const SensedCloud cloud = Reproject(disparity, kInvalid16, c, Eigen::Isometry3d::Identity(), options);
  ASSERT_EQ(cloud.kept_count, static_cast<size_t>(kWidth) * kHeight);
  cv::Mat disparity_px, xyz;
  disparity.convertTo(disparity_px, CV_32F, 1.0 / 16.0);
  cv::reprojectImageTo3D(disparity_px, xyz, c.Q, false, CV_32F);
  for (size_t k = 0; k < cloud.kept_count; ++k) {
    const cv::Vec3f ref = xyz.at<cv::Vec3f>(static_cast<int>(k / kWidth), static_cast<int>(k % kWidth));
    const Eigen::Vector3d point_in_rect_left = r1 * cloud.points_in_tanker[k];
    const Eigen::Vector3d expected(ref[0], ref[1], ref[2]);
    ASSERT_LT((point_in_rect_left - expected).norm(), 2e-6 * expected.norm()) << "pixel " << k;
  }
}

// Which points pass the depth filter decides the kept set: whether Q is a
// rectifying one (its depth tabulated per disparity) or a general one (u and
// v in its last rows, evaluated per pixel), the kept points are those eq. 1
// puts in range, in row-major order.
TEST(Reprojection, KeepsThePointsEquationOnePutsInRangeForAnyQ) {
  for (const bool general : {false, true}) {
    SCOPED_TRACE(general ? "general Q" : "rectifying Q");
    StereoCalibration c = IdealCalibration(TestRig());
    if (general) c.Q.at<double>(3, 0) = 0.01;  // w, so the depth, varies along the rows
    cv::Mat disparity(kHeight, kWidth, CV_16S);
    cv::RNG rng(5);
    rng.fill(disparity, cv::RNG::UNIFORM, -16, 16 * 30);
    ReprojectionOptions options = PlainOptions();
    options.keep_one_in = 1;
    options.max_depth_m = 25.0;  // about half of the disparities, 0 to 30 px, fall short of 18 px
    const SensedCloud cloud = Reproject(disparity, kInvalid16, c, Eigen::Isometry3d::Identity(), options);
    Eigen::Matrix4d q;
    for (int i = 0; i < 16; ++i) q(i / 4, i % 4) = c.Q.at<double>(i / 4, i % 4);
    std::vector<Eigen::Vector3d> expected;
    for (int v = 0; v < kHeight; ++v) {
      for (int u = 0; u < kWidth; ++u) {
        const short value = disparity.at<short>(v, u);
        if (value <= kInvalid16) continue;
        const Eigen::Vector4d h = q * Eigen::Vector4d(u, v, value / 16.0, 1.0);
        const Eigen::Vector3d p = h.head<3>() / h.w();
        if (p.allFinite() && p.z() > options.min_depth_m && p.z() <= options.max_depth_m) expected.push_back(p);
      }
    }
    ASSERT_GT(expected.size(), 1000u);
    ASSERT_LT(expected.size(), static_cast<size_t>(kWidth) * kHeight * 3 / 4);
    ASSERT_EQ(cloud.kept_count, expected.size());
    EXPECT_EQ(0,
              std::memcmp(cloud.points_in_tanker.data(), expected.data(), expected.size() * sizeof(Eigen::Vector3d)));
  }
}

TEST(Reprojection, IsBitwiseRepeatable) {
  const StereoRig rig = TestRig();
  const StereoCalibration c = IdealCalibration(rig);
  cv::Mat disparity(kHeight, kWidth, CV_16S);
  cv::RNG rng(11);
  rng.fill(disparity, cv::RNG::UNIFORM, -16, 16 * 48);
  const SensedCloud a = Reproject(disparity, kInvalid16, c, rig.left.tanker_from_camera, PlainOptions());
  const SensedCloud b = Reproject(disparity, kInvalid16, c, rig.left.tanker_from_camera, PlainOptions());
  ASSERT_EQ(a.kept_count, b.kept_count);
  ASSERT_GT(a.kept_count, 0u);
  EXPECT_EQ(0,
            std::memcmp(a.points_in_tanker.data(), b.points_in_tanker.data(), a.kept_count * sizeof(Eigen::Vector3d)));
}

TEST(Reprojection, DisparityOffsetIsSubtractedBeforeEquationOne) {
  const StereoRig rig = TestRig();
  const StereoCalibration c = IdealCalibration(rig);
  const cv::Mat disparity(kHeight, kWidth, CV_16S, cv::Scalar(short{200}));  // 12.5 px
  ReprojectionOptions options = PlainOptions();
  options.disparity_offset_px = 0.5;
  const SensedCloud cloud = Reproject(disparity, kInvalid16, c, Eigen::Isometry3d::Identity(), options);
  ASSERT_FALSE(cloud.points_in_tanker.empty());
  const double expected_z = rig.left.intrinsics.fx_px * rig.Baseline() / 12.0;
  EXPECT_NEAR(cloud.points_in_tanker.front().z(), expected_z, 1e-9);
}

// A rectified pair whose right image is the left one moved by exactly 12 px:
// the refinement finds 12 px from any start within a pixel.
TEST(Reprojection, RefinedDisparitiesLoseTheMatcherBiasAndKeepTheOffset) {
  const StereoRig rig = TestRig();
  const StereoCalibration c = IdealCalibration(rig);
  cv::Mat noise(kHeight, kWidth + 12, CV_32F), texture;
  cv::RNG rng(7);
  rng.fill(noise, cv::RNG::UNIFORM, 0.0, 255.0);
  cv::GaussianBlur(noise, texture, cv::Size(0, 0), 1.0);
  cv::Mat left, right;
  texture(cv::Rect(0, 0, kWidth, kHeight)).convertTo(left, CV_8U);
  texture(cv::Rect(12, 0, kWidth, kHeight)).convertTo(right, CV_8U);
  // right(x) = texture(x + 12): left pixel u shows what right pixel u - 12 shows.
  const SubpixelRefiner refiner(left, right, SubpixelOptions{});
  const cv::Mat disparity(kHeight, kWidth, CV_16S, cv::Scalar(short{200}));  // the matcher says 12.5 px
  const auto median_disparity = [&](double matcher_bias_px, double offset_px) {
    ReprojectionOptions options = PlainOptions();
    options.matcher_bias_px = matcher_bias_px;
    options.disparity_offset_px = offset_px;
    options.keep_one_in = 1;
    const SensedCloud cloud = Reproject(disparity, kInvalid16, c, Eigen::Isometry3d::Identity(), options, &refiner);
    std::vector<double> d;
    for (const Eigen::Vector3d& pixel : cloud.pixels) d.push_back(pixel.z());
    EXPECT_GT(d.size(), 1000u);
    std::nth_element(d.begin(), d.begin() + static_cast<std::ptrdiff_t>(d.size() / 2), d.end());
    return d[d.size() / 2];
  };
  EXPECT_NEAR(median_disparity(0.0, 0.0), 12.0, 0.01);
  EXPECT_NEAR(median_disparity(0.3, 0.0), 12.0, 0.01);  // a better start, the same answer
  EXPECT_NEAR(median_disparity(0.0, 0.25), 11.75, 0.01);
}

}  // namespace
}  // namespace aar
