// Brown-Conrady lens model (common/lens.h) and the rig schema that carries it
// (aar-rig/2): the inverse and Jacobian against the forward model, the fold
// test, refusals with their reasons, and old rigs still read.

#include "aar/lens.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <random>

#include "../test_support.h"
#include "aar/error.h"
#include "aar/file_io.h"
#include "aar/rig.h"
#include "aar/stereo_calibration.h"

namespace aar {
namespace {

using test::SourcePath;

const BrownConrady kLens{-0.15, 0.05, 1e-4, -1e-4, 0.0};

using test::ErrorOf;

TEST(Lens, UndistortInvertsDistortOverTheImage) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> ux(-0.6, 0.6), uy(-0.45, 0.45);
  double worst = 0.0;
  for (int i = 0; i < 2000; ++i) {
    const Eigen::Vector2d x(ux(rng), uy(rng));
    const std::optional<Eigen::Vector2d> back = Undistort(kLens, Distort(kLens, x));
    ASSERT_TRUE(back.has_value()) << x.transpose();
    worst = std::max(worst, (*back - x).norm());
  }
  EXPECT_LT(worst, 1e-12);
}

TEST(Lens, JacobianMatchesFiniteDifferences) {
  const Eigen::Vector2d x(0.41, -0.33);
  const Eigen::Matrix2d j = DistortJacobian(kLens, x);
  const double h = 1e-6;
  for (int c = 0; c < 2; ++c) {
    Eigen::Vector2d dx = Eigen::Vector2d::Zero();
    dx(c) = h;
    const Eigen::Vector2d numeric = (Distort(kLens, x + dx) - Distort(kLens, x - dx)) / (2 * h);
    EXPECT_NEAR(numeric(0), j(0, c), 1e-8);
    EXPECT_NEAR(numeric(1), j(1, c), 1e-8);
  }
}

TEST(Lens, RadialFoldIsFoundExactly) {
  // k1 only: slope 1 + 3 k1 r^2 vanishes at r^2 = -1 / (3 k1).
  const BrownConrady k1_only{-0.3, 0, 0, 0, 0};
  EXPECT_TRUE(RadiallyMonotonic(k1_only, 1.0 / 0.9 - 1e-9));
  EXPECT_FALSE(RadiallyMonotonic(k1_only, 1.0 / 0.9 + 1e-9));
  // A dip of the slope between 0 and r^2 is caught even where the slope at r^2 is positive again.
  const BrownConrady dip{-0.8, 0.2, 0, 0, 0};  // slope 1 - 2.4 s + s^2: negative on s in (0.54, 1.86)
  EXPECT_FALSE(RadiallyMonotonic(dip, 2.0));
  EXPECT_TRUE(RadiallyMonotonic(dip, 0.5));
  EXPECT_TRUE(RadiallyMonotonic(kLens, 1.0));
}

TEST(Lens, ProjectAppliesTheDistortionAndRefusesFoldedRays) {
  Intrinsics k;
  k.distortion = kLens;
  const Eigen::Vector3d p(0.4, -0.3, 1.0);
  const Eigen::Vector2d d = Distort(kLens, Eigen::Vector2d(0.4, -0.3));
  const Eigen::Vector2d pixel = *k.Project(p);
  EXPECT_NEAR(pixel.x(), 900.0 * d.x() + 511.5, 1e-9);
  EXPECT_NEAR(pixel.y(), 900.0 * d.y() + 383.5, 1e-9);
  // Far off axis the k1-only model folds back towards the centre: no pixel, not a false one.
  k.distortion = BrownConrady{-0.3, 0, 0, 0, 0};
  EXPECT_FALSE(k.Project(Eigen::Vector3d(3.0, 0.0, 1.0)).has_value());
}

TEST(Lens, FoldingDistortionIsRefusedWithTheReason) {
  const std::string message = ErrorOf([] {
    CheckDistortionInImage({-0.6, 0.05, 0, 0, 0}, 900, 900, 511.5, 383.5, 1024, 768, "rig.json");
  });
  EXPECT_NE(message.find("rig.json: lens distortion (k1 -0.6, k2 0.05, p1 0, p2 0, k3 0) is not one-to-one inside "
                         "the image"),
            std::string::npos)
      << message;
  EXPECT_NE(message.find("the radial mapping stops increasing at r = 0.779"), std::string::npos) << message;
  EXPECT_EQ(ErrorOf([] { CheckDistortionInImage(kLens, 900, 900, 511.5, 383.5, 1024, 768, "rig.json"); }), "");
}

TEST(RigSchema, DistortedRigReadsAndWritesAsSchema2) {
  const StereoRig rig = LoadRig(SourcePath("scenes/rig-distorted.json"));
  EXPECT_TRUE(HasDistortion(rig));
  EXPECT_EQ(rig.left.intrinsics.distortion, (BrownConrady{-0.15, 0.05, 1e-4, -1e-4, 0.0}));
  EXPECT_EQ(rig.right.intrinsics.distortion, (BrownConrady{-0.14, 0.045, -1.2e-4, 0.8e-4, 0.0}));
  const nlohmann::json j = RigToJson(rig);
  EXPECT_EQ(j.at("schema"), "aar-rig/2");
  const StereoRig back = RigFromJson(j, "sidecar");
  EXPECT_EQ(back.left.intrinsics.distortion, rig.left.intrinsics.distortion);
  EXPECT_EQ(back.right.intrinsics.distortion, rig.right.intrinsics.distortion);
  // The ideal calibration carries the coefficients in OpenCV's order; rectification stays the identity.
  const StereoCalibration ideal = IdealCalibration(rig);
  EXPECT_DOUBLE_EQ(ideal.D1.at<double>(0, 0), -0.15);
  EXPECT_DOUBLE_EQ(ideal.D1.at<double>(0, 2), 1e-4);
  EXPECT_DOUBLE_EQ(ideal.D2.at<double>(0, 1), 0.045);
  EXPECT_DOUBLE_EQ(ideal.D2.at<double>(0, 3), 0.8e-4);
  EXPECT_EQ(cv::norm(ideal.R1 - cv::Mat::eye(3, 3, CV_64F)), 0.0);
}

TEST(RigSchema, PinholeRigsStaySchema1AndOldRigsStillRead) {
  const StereoRig rig = LoadRig(SourcePath("scenes/rig.json"));
  EXPECT_FALSE(HasDistortion(rig));
  const nlohmann::json j = RigToJson(rig);
  EXPECT_EQ(j.at("schema"), "aar-rig/1");
  EXPECT_FALSE(j.at("cameras").at("left").contains("distortion"));
  nlohmann::json no_schema = j;
  no_schema.erase("schema");  // rigs from before the schema key
  EXPECT_FALSE(HasDistortion(RigFromJson(no_schema, "old.json")));
  const StereoCalibration ideal = IdealCalibration(rig);
  EXPECT_EQ(cv::countNonZero(ideal.D1 != 0) + cv::countNonZero(ideal.D2 != 0), 0);
}

TEST(RigSchema, BadDistortionEntriesAreRefused) {
  nlohmann::json j = RigToJson(LoadRig(SourcePath("scenes/rig-distorted.json")));
  nlohmann::json v1 = j;
  v1["schema"] = "aar-rig/1";
  EXPECT_NE(ErrorOf([&] { RigFromJson(v1, "r.json"); }).find("r.json: camera left: 'distortion' needs schema"),
            std::string::npos);
  nlohmann::json unknown = j;
  unknown["schema"] = "aar-rig/9";
  EXPECT_NE(ErrorOf([&] { RigFromJson(unknown, "r.json"); }).find("r.json: unknown schema \"aar-rig/9\""),
            std::string::npos);
  nlohmann::json missing = j;
  missing["cameras"]["right"]["distortion"].erase("k3");
  EXPECT_NE(ErrorOf([&] { RigFromJson(missing, "r.json"); }).find("camera right: distortion: missing number 'k3'"),
            std::string::npos);
  nlohmann::json folded = j;
  folded["cameras"]["right"]["distortion"]["k1"] = -0.7;
  EXPECT_NE(ErrorOf([&] { RigFromJson(folded, "r.json"); }).find("is not one-to-one inside the image"),
            std::string::npos);
}

}  // namespace
}  // namespace aar
