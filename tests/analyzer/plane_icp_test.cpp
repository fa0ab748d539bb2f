// Robust noise-weighted point-to-plane ICP on synthetic clouds.

#include "aar/analyzer/plane_icp.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

#include "aar/analyzer/reference_model.h"
#include "aar/error.h"
#include "aar/random_stream.h"
#include "test_meshes.h"

namespace aar {
namespace {

// An L-shaped receiver of three boxes (no symmetry that leaves a pose free).
TriangleMesh Receiver() {
  TriangleMesh mesh;
  test::AddBox(mesh, Eigen::Vector3d::Zero(), {6.0, 0.8, 0.8});
  test::AddBox(mesh, {0.5, 0.0, 0.0}, {1.0, 7.0, 0.15});
  test::AddBox(mesh, {-5.5, 0.0, 1.5}, {0.4, 0.15, 1.5});
  return mesh;
}

Eigen::Isometry3d TruePose() {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = (Eigen::AngleAxisd(0.02, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(-0.01, Eigen::Vector3d::UnitY()))
                   .toRotationMatrix();
  t.translation() = Eigen::Vector3d(-47.7, 0.3, -18.9);
  return t;
}

StereoNoiseGeometry Geometry() {
  StereoNoiseGeometry g;
  g.camera_centre_in_tanker = Eigen::Vector3d(-20.0, 0.0, -2.9);
  g.optical_axis_in_tanker = (Eigen::Vector3d(-47.7, 0.0, -18.9) - g.camera_centre_in_tanker).normalized();
  return g;
}

class PlaneIcpConverges : public ::testing::TestWithParam<PlanePairing> {};

TEST_P(PlaneIcpConverges, FromHalfAMetreAndFiveDegreesWithinTwentyIterations) {
  const ReferenceModel model = SampleSurfaceWithNormals(Receiver(), 8000, 7);
  // The sensed cloud: other samples of the same surface at the true pose.
  const ReferenceModel other = SampleSurfaceWithNormals(Receiver(), 3000, 8);
  std::vector<Eigen::Vector3d> sensed;
  for (const Eigen::Vector3d& p : other.points_in_receiver) sensed.push_back(TruePose() * p);
  Eigen::Isometry3d initial = TruePose();
  initial.translation() += Eigen::Vector3d(0.3, -0.3, 0.3);
  initial.linear() = Eigen::AngleAxisd(5.0 * M_PI / 180.0, Eigen::Vector3d(1, 1, 1).normalized()) * initial.linear();
  PlaneIcpOptions options;
  options.pairing = GetParam();
  const PlaneIcpRegistration icp(model.points_in_receiver, model.normals_in_receiver, Geometry(), options);
  const RegistrationResult result = icp.Register(sensed, initial);
  EXPECT_TRUE(result.converged);
  EXPECT_LE(result.iterations, 20);
  const Eigen::Isometry3d error = TruePose().inverse() * result.tanker_from_receiver;
  EXPECT_LT(error.translation().norm(), 0.01);
  EXPECT_LT(Eigen::AngleAxisd(error.linear()).angle() * 180.0 / M_PI, 0.05);
}

INSTANTIATE_TEST_SUITE_P(Pairings, PlaneIcpConverges,
                         ::testing::Values(PlanePairing::kSensedToModel, PlanePairing::kSymmetric));

TEST(PlaneIcp, PairsSensedPointsWithTheFullSurfaceWhenGiven) {
  // The model is half the receiver (a "shell"); the sensed cloud covers all
  // of it, so without the full surface its other half pairs with wrong points.
  const ReferenceModel full = SampleSurfaceWithNormals(Receiver(), 8000, 7);
  ReferenceModel half;
  for (size_t i = 0; i < full.points_in_receiver.size(); ++i) {
    if (full.points_in_receiver[i].z() >= 0.0) {
      half.points_in_receiver.push_back(full.points_in_receiver[i]);
      half.normals_in_receiver.push_back(full.normals_in_receiver[i]);
    }
  }
  std::vector<Eigen::Vector3d> sensed;
  for (const Eigen::Vector3d& p : SampleSurfaceWithNormals(Receiver(), 3000, 8).points_in_receiver) {
    sensed.push_back(TruePose() * p);
  }
  Eigen::Isometry3d initial = TruePose();
  initial.translation() += Eigen::Vector3d(0.2, 0.1, -0.2);
  PlaneIcpOptions options;
  options.pairing = PlanePairing::kSensedToModel;
  PlaneIcpRegistration icp(half.points_in_receiver, half.normals_in_receiver, Geometry(), options);
  EXPECT_THROW(icp.SetSensedPairingSurface(full.points_in_receiver, {}), Error);
  icp.SetSensedPairingSurface(full.points_in_receiver, full.normals_in_receiver);
  const RegistrationResult result = icp.Register(sensed, initial);
  EXPECT_TRUE(result.converged);
  const Eigen::Isometry3d error = TruePose().inverse() * result.tanker_from_receiver;
  EXPECT_LT(error.translation().norm(), 0.01);
  EXPECT_LT(Eigen::AngleAxisd(error.linear()).angle() * 180.0 / M_PI, 0.05);
}

TEST(PlaneIcp, ModelPullFadesWithTheScaleAgainstTheDepthNoise) {
  // A stereo-like cloud: the wing tips and the nose missing, every point
  // moved along its viewing ray by the range-squared depth noise of 0.1 px at
  // f b = 450 px m (sigma_ray about 0.24 m here). The model-to-sensed pairs
  // weigh sigma_ray^2 / (sigma_ray^2 + t^2): with t far above sigma_ray the
  // result is the sensed-to-model pairing's, and a moderate t lies between.
  const ReferenceModel model = SampleSurfaceWithNormals(Receiver(), 8000, 7);
  const StereoNoiseGeometry geometry = Geometry();
  std::mt19937 rng(11);
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::vector<Eigen::Vector3d> sensed;
  for (const Eigen::Vector3d& p : SampleSurfaceWithNormals(Receiver(), 3000, 8).points_in_receiver) {
    if (std::abs(p.y()) > 2.8 || p.x() > 2.4) continue;
    const Eigen::Vector3d s = TruePose() * p;
    const Eigen::Vector3d offset = s - geometry.camera_centre_in_tanker;
    const double depth = offset.dot(geometry.optical_axis_in_tanker);
    const double sigma_ray = depth * offset.norm() * 0.1 / geometry.focal_times_baseline_px_m;
    sensed.push_back(s + offset.normalized() * sigma_ray * gauss(rng));
  }
  const auto register_with = [&](PlanePairing pairing, double pull_scale_m) {
    PlaneIcpOptions options;
    options.pairing = pairing;
    options.model_pull_scale_m = pull_scale_m;
    const PlaneIcpRegistration icp(model.points_in_receiver, model.normals_in_receiver, geometry, options);
    const RegistrationResult result = icp.Register(sensed, TruePose());
    EXPECT_TRUE(result.converged);
    return result.tanker_from_receiver;
  };
  const Eigen::Isometry3d sensed_only = register_with(PlanePairing::kSensedToModel, 0.0);
  const Eigen::Isometry3d faded = register_with(PlanePairing::kSymmetric, 1e4);
  const Eigen::Isometry3d full = register_with(PlanePairing::kSymmetric, 0.0);
  const Eigen::Isometry3d half = register_with(PlanePairing::kSymmetric, 0.5);
  EXPECT_LT((faded.translation() - sensed_only.translation()).norm(), 1e-4);
  EXPECT_GT((full.translation() - sensed_only.translation()).norm(), 1e-3);  // the pulls matter here
  const double span = (full.translation() - sensed_only.translation()).norm();
  EXPECT_LT((half.translation() - sensed_only.translation()).norm(), span);
  EXPECT_LT((half.translation() - full.translation()).norm(), span);
  for (const Eigen::Isometry3d& t : {sensed_only, full, half}) {
    EXPECT_LT((TruePose().inverse() * t).translation().norm(), 0.1);  // all near the truth
  }
  PlaneIcpOptions bad;
  bad.model_pull_scale_m = -1.0;
  EXPECT_THROW(bad.Check(), Error);
}

TEST(PlaneIcp, MahalanobisPairingConvergesOnTheSurfacesFacingTheCameras) {
  // What a stereo pair sees of the receiver at about 55 m: the samples whose
  // surface faces the left camera. The metric pairing searches only those
  // faces of the model, in the camera's scaled disparity space.
  const ReferenceModel model = SampleSurfaceWithNormals(Receiver(), 8000, 7);
  const StereoNoiseGeometry geometry = Geometry();
  const ReferenceModel samples = SampleSurfaceWithNormals(Receiver(), 3000, 8);
  std::vector<Eigen::Vector3d> sensed;
  for (size_t i = 0; i < samples.points_in_receiver.size(); ++i) {
    const Eigen::Vector3d s = TruePose() * samples.points_in_receiver[i];
    if ((TruePose().linear() * samples.normals_in_receiver[i]).dot(s - geometry.camera_centre_in_tanker) < 0.0) {
      sensed.push_back(s);
    }
  }
  ASSERT_GT(sensed.size(), 500u);
  Eigen::Isometry3d initial = TruePose();
  initial.translation() += Eigen::Vector3d(0.3, -0.3, 0.3);
  initial.linear() = Eigen::AngleAxisd(3.0 * M_PI / 180.0, Eigen::Vector3d(1, 1, 1).normalized()) * initial.linear();
  for (const PlaneResidual residual : {PlaneResidual::kMetric, PlaneResidual::kDisparity, PlaneResidual::kMetricRay}) {
    SCOPED_TRACE(ToString(residual));
    PlaneIcpOptions options;
    options.pairing = PlanePairing::kMahalanobis;
    options.residual = residual;
    const PlaneIcpRegistration icp(model.points_in_receiver, model.normals_in_receiver, geometry, options);
    const RegistrationResult result = icp.Register(sensed, initial);
    EXPECT_TRUE(result.converged);
    EXPECT_LE(result.iterations, 40);
    const Eigen::Isometry3d error = TruePose().inverse() * result.tanker_from_receiver;
    EXPECT_LT(error.translation().norm(), 0.02);
    EXPECT_LT(Eigen::AngleAxisd(error.linear()).angle() * 180.0 / M_PI, 0.1);
  }
}

// Depth noise along the rays tilts the metric residual's estimate: its rotation turns about the noisy sensed point
// (errors in the variables). Turning it about where the ray meets the model's plane (metric-ray) does not.
TEST(PlaneIcp, TheRayLeverArmAndTheNoiseBiasCorrectionRemoveTheNoisesTilt) {
  const ReferenceModel model = SampleSurfaceWithNormals(Receiver(), 8000, 7);
  const StereoNoiseGeometry geometry = Geometry();
  const ReferenceModel samples = SampleSurfaceWithNormals(Receiver(), 6000, 8);
  RandomStream random(3);
  std::vector<Eigen::Vector3d> sensed;
  for (size_t i = 0; i < samples.points_in_receiver.size(); ++i) {
    const Eigen::Vector3d s = TruePose() * samples.points_in_receiver[i];
    const Eigen::Vector3d ray = s - geometry.camera_centre_in_tanker;
    if ((TruePose().linear() * samples.normals_in_receiver[i]).dot(ray) >= 0.0) continue;
    // 0.3 px of disparity noise at about 14 px: 2 % of the depth.
    sensed.push_back(geometry.camera_centre_in_tanker + ray * (1.0 + 0.3 / 14.0 * random.Normal()));
  }
  double noise_scale = 0.0;
  const auto angle_error_deg = [&](PlaneResidual residual, bool correction, double model_noise_px) {
    PlaneIcpOptions options;
    options.pairing = PlanePairing::kMahalanobis;
    options.residual = residual;
    options.disparity_noise_px = model_noise_px;
    options.noise_bias_correction = correction;
    const PlaneIcpRegistration icp(model.points_in_receiver, model.normals_in_receiver, geometry, options);
    const RegistrationResult result = icp.Register(sensed, TruePose());
    noise_scale = result.noise_scale;
    const Eigen::Isometry3d error = TruePose().inverse() * result.tanker_from_receiver;
    return Eigen::AngleAxisd(error.linear()).angle() * 180.0 / M_PI;
  };
  const double metric = angle_error_deg(PlaneResidual::kMetric, false, 0.3);
  EXPECT_EQ(noise_scale, 0.0);
  const double ray = angle_error_deg(PlaneResidual::kMetricRay, false, 0.3);
  const double corrected = angle_error_deg(PlaneResidual::kMetric, true, 0.3);
  const double scale_at_truth = noise_scale;
  // The model's noise a third of the points': the step follows the residuals' own scale.
  const double corrected_low_model = angle_error_deg(PlaneResidual::kMetric, true, 0.1);
  std::printf(
      "rotation error: metric %.3f deg, metric-ray %.3f deg, corrected %.3f deg (noise scale %.2f), "
      "corrected with the model's noise at 0.1 px %.3f deg (noise scale %.2f)\n",
      metric, ray, corrected, scale_at_truth, corrected_low_model, noise_scale);
  EXPECT_LT(ray, 0.5 * metric);
  EXPECT_LT(corrected, 0.5 * metric);
  EXPECT_LT(corrected_low_model, 0.5 * metric);
  EXPECT_GT(noise_scale, 1.4 * scale_at_truth);  // less than 3x: the gate at 3 model sigmas cuts the tails

  PlaneIcpOptions wrong;
  wrong.residual = PlaneResidual::kMetricRay;
  wrong.noise_bias_correction = true;
  EXPECT_THROW(wrong.Check(), Error);
}

TEST(PlaneIcp, ResidualNames) {
  EXPECT_EQ(ParsePlaneResidual("disparity"), PlaneResidual::kDisparity);
  EXPECT_EQ(ParsePlaneResidual("metric"), PlaneResidual::kMetric);
  EXPECT_EQ(ToString(PlaneResidual::kDisparity), "disparity");
  EXPECT_EQ(ParsePlaneResidual("metric-ray"), PlaneResidual::kMetricRay);
  EXPECT_EQ(ToString(PlaneResidual::kMetricRay), "metric-ray");
  EXPECT_THROW(ParsePlaneResidual("pixels"), Error);
}

TEST(PlaneIcp, RejectsModelsWithoutNormalsAndEmptyClouds) {
  const ReferenceModel model = SampleSurfaceWithNormals(Receiver(), 100, 1);
  EXPECT_THROW(PlaneIcpRegistration(model.points_in_receiver, {}, Geometry()), Error);
  const PlaneIcpRegistration icp(model.points_in_receiver, model.normals_in_receiver, Geometry());
  EXPECT_THROW(icp.Register({}, Eigen::Isometry3d::Identity()), Error);
  EXPECT_EQ(ParsePlanePairing(ToString(PlanePairing::kSymmetric)), PlanePairing::kSymmetric);
  EXPECT_EQ(ParsePlanePairing(ToString(PlanePairing::kMahalanobis)), PlanePairing::kMahalanobis);
  EXPECT_THROW(ParsePlanePairing("both"), Error);
}

}  // namespace
}  // namespace aar
