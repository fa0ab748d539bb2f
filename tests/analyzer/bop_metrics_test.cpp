// BOP's pose errors and scores, and ADD / ADD-S, against hand-computed
// values on a cube (bop_metrics.h).

#include "aar/analyzer/bop_metrics.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "aar/analyzer/frame_results.h"
#include "aar/error.h"
#include "test_meshes.h"

namespace aar {
namespace {

// A 1 m cube about the model origin, 10 m in front of a camera with a focal
// length of 100 px and the principal point at (0, 0).
struct CubeCase {
  TriangleMesh mesh;
  Intrinsics camera;
  Eigen::Isometry3d cam_from_model_truth = Eigen::Isometry3d::Identity();
  CubeCase() {
    test::AddBox(mesh, Eigen::Vector3d::Zero(), Eigen::Vector3d(0.5, 0.5, 0.5));
    camera.width_px = 1280;
    camera.height_px = 960;
    camera.fx_px = camera.fy_px = 100.0;
    camera.cx_px = camera.cy_px = 0.0;
    cam_from_model_truth.translation() = Eigen::Vector3d(0.0, 0.0, 10.0);
  }
};

TEST(BopMetrics, DiameterIsTheLargestVertexDistance) {
  const CubeCase c;
  EXPECT_NEAR(BopObject(c.mesh).diameter_m(), std::sqrt(3.0), 1e-12);
  EXPECT_EQ(BopObject(c.mesh).vertices().size(), 8u);
  TriangleMesh point;
  point.vertices = {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
  EXPECT_THROW(BopObject{point}, Error);
}

TEST(BopMetrics, DiameterEqualsTheLargestPairwiseDistanceOfAnyCloud) {
  // The pruned search against every pair, on elongated and round clouds.
  std::mt19937 random(7);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  for (const Eigen::Vector3d& scale : {Eigen::Vector3d(8.0, 1.0, 0.5), Eigen::Vector3d(1.0, 1.0, 1.0)}) {
    TriangleMesh cloud;
    for (int i = 0; i < 2000; ++i) {
      cloud.vertices.push_back(Eigen::Vector3d(uniform(random), uniform(random), uniform(random)).cwiseProduct(scale));
    }
    double every_pair_sq = 0.0;
    for (size_t i = 0; i < cloud.vertices.size(); ++i) {
      for (size_t k = i + 1; k < cloud.vertices.size(); ++k) {
        every_pair_sq = std::max(every_pair_sq, (cloud.vertices[i] - cloud.vertices[k]).squaredNorm());
      }
    }
    EXPECT_EQ(BopObject(cloud).diameter_m(), std::sqrt(every_pair_sq));
  }
}

TEST(BopMetrics, ATranslationMovesEveryVertexByItsLength) {
  // 0.1 m along x: every vertex moves 0.1 m; the nearest true vertex of each
  // moved one is its own (the others are 0.9 m and more away); the nearest
  // face (z = 9.5 m) moves 100 * 0.1 / 9.5 px in the image.
  const CubeCase c;
  Eigen::Isometry3d estimate = c.cam_from_model_truth;
  estimate.translation().x() += 0.1;
  const PoseErrorMetrics m = ComputePoseErrorMetrics(BopObject(c.mesh), c.camera, estimate, c.cam_from_model_truth);
  EXPECT_NEAR(m.mssd_m, 0.1, 1e-12);
  EXPECT_NEAR(m.add_m, 0.1, 1e-12);
  EXPECT_NEAR(m.adds_m, 0.1, 1e-12);
  EXPECT_NEAR(m.mspd_px, 100.0 * 0.1 / 9.5, 1e-9);
}

TEST(BopMetrics, ASymmetryOfTheShapeCostsNothingInAddS) {
  // A quarter turn about the model's z axis maps the cube onto itself: every
  // vertex lands on another one (ADD-S 0), but each moved by |(x, y) -
  // (-y, x)| = sqrt(2) * sqrt(0.5) = 1 m (MSSD = ADD = 1); in the image the
  // near face's corners move 100 * 1 / 9.5 px.
  const CubeCase c;
  const Eigen::Isometry3d estimate = c.cam_from_model_truth * Eigen::AngleAxisd(0.5 * M_PI, Eigen::Vector3d::UnitZ());
  const PoseErrorMetrics m = ComputePoseErrorMetrics(BopObject(c.mesh), c.camera, estimate, c.cam_from_model_truth);
  EXPECT_NEAR(m.mssd_m, 1.0, 1e-12);
  EXPECT_NEAR(m.add_m, 1.0, 1e-12);
  EXPECT_NEAR(m.adds_m, 0.0, 1e-12);
  EXPECT_NEAR(m.mspd_px, 100.0 / 9.5, 1e-9);
}

TEST(BopMetrics, AVertexBehindTheCameraIsInfinitelyFarInTheImage) {
  const CubeCase c;
  Eigen::Isometry3d estimate = c.cam_from_model_truth;
  estimate.translation().z() = 0.2;  // the near face at z = -0.3
  const PoseErrorMetrics m = ComputePoseErrorMetrics(BopObject(c.mesh), c.camera, estimate, c.cam_from_model_truth);
  EXPECT_EQ(m.mspd_px, std::numeric_limits<double>::infinity());
  EXPECT_NEAR(m.mssd_m, 9.8, 1e-12);
}

TEST(BopMetrics, ScoresAverageTheRecallOverBopsThresholds) {
  // Diameter 1 m, a 1280 px image (r = 2: MSPD thresholds 10, 20, ..., 100 px).
  // One estimate with MSSD 0.12 m (below 8 of the 10 thresholds 0.05..0.5)
  // and MSPD 12 px (below 9 of 10), ADD 0.05 m (< 0.1), ADD-S 0.2 m (not);
  // one frame without an estimate (a miss everywhere).
  PoseErrorMetrics e;
  e.mssd_m = 0.12;
  e.mspd_px = 12.0;
  e.add_m = 0.05;
  e.adds_m = 0.2;
  const BopScores s = ScoreBop({e, std::nullopt}, BopScale{1.0, 1280});
  EXPECT_EQ(s.targets, 2u);
  EXPECT_NEAR(s.ar_mssd, 0.4, 1e-12);
  EXPECT_NEAR(s.ar_mspd, 0.45, 1e-12);
  EXPECT_NEAR(s.ar_mssd_mspd, 0.425, 1e-12);
  EXPECT_NEAR(s.add_recall, 0.5, 1e-12);
  EXPECT_NEAR(s.adds_recall, 0.0, 1e-12);
  EXPECT_EQ(ScoreBop({}, BopScale{1.0, 1280}).targets, 0u);
  EXPECT_THROW(ScoreBop({e}, BopScale{0.0, 1280}), Error);
}

TEST(BopMetrics, ResultsFileHoldsTheOkFramesInTheCamera) {
  // The camera 2 m behind the tanker origin, looking along the tanker's x:
  // camera_from_tanker maps tanker x to camera z.
  Eigen::Isometry3d camera_from_tanker = Eigen::Isometry3d::Identity();
  camera_from_tanker.linear() << 0, 1, 0, 0, 0, 1, 1, 0, 0;
  camera_from_tanker.translation() = Eigen::Vector3d(0.0, 0.0, 2.0);
  FrameResult ok, failed;
  ok.frame = 7;
  ok.estimate.translation_m = Eigen::Vector3d(30.0, 1.0, -2.0);
  ok.times.total_ms = 12.5;
  failed.frame = 8;
  failed.status = "too few sensed points";
  EXPECT_EQ(FormatBopResults({ok, failed}, camera_from_tanker),
            "scene_id,im_id,obj_id,score,R,t,time\n"
            "1,7,1,1,0.000000000 1.000000000 0.000000000 0.000000000 0.000000000 1.000000000 1.000000000 "
            "0.000000000 0.000000000,1000.000000 -2000.000000 32000.000000,0.012500\n");
}

TEST(BopMetrics, FrameResultsCarryTheErrorsThroughTheCsv) {
  FrameResult with, without;
  with.frame = 1;
  with.bop_errors = PoseErrorMetrics{0.25, 3.5, 0.125, 0.0625, std::nullopt};
  without.frame = 2;
  without.status = "failed";
  const std::vector<FrameResult> back = ParseFrameResults(FormatFrameResults({with, without}), "test");
  ASSERT_EQ(back.size(), 2u);
  ASSERT_TRUE(back[0].bop_errors.has_value());
  EXPECT_EQ(back[0].bop_errors->mssd_m, 0.25);
  EXPECT_EQ(back[0].bop_errors->mspd_px, 3.5);
  EXPECT_EQ(back[0].bop_errors->add_m, 0.125);
  EXPECT_EQ(back[0].bop_errors->adds_m, 0.0625);
  EXPECT_FALSE(back[1].bop_errors.has_value());
}

}  // namespace
}  // namespace aar
