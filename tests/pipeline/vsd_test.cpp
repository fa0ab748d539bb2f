// VSD on the renderer's own images: the receiver mesh rasterized by the
// analyzer at the true pose (depth_raster.h) against the depth truth
// aar-render wrote, and the run's AR_VSD (vsd.h, bop_metrics.h).

#include "aar/analyzer/vsd.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "aar/analyzer/analysis_run.h"
#include "aar/analyzer/mesh.h"
#include "aar/analyzer/stereo_truth.h"
#include "aar/dataset.h"
#include "aar/file_io.h"
#include "pipeline_support.h"

namespace aar {
namespace {

namespace fs = std::filesystem;
using test::Quote;
using test::SharedDatasets;

// At the true pose the analyzer's raster of the receiver mesh is the surface
// the renderer drew: measured on the 8 near-contact frames (lavapipe, x16),
// 99.99-100 % of the receiver's pixels agree within 1 mm, so an estimate at
// the truth has e_VSD 0 and one a pixel aside 0.033 (the outline's share).
TEST(PipelineVsd, TheTruthAgreesWithTheRenderersDepth) {
  ASSERT_DATASETS();
  const fs::path dataset = SharedDatasets().near_contact;
  const OpenedDataset opened = OpenedDataset::Open(dataset);
  const TriangleMesh mesh = LoadReceiverMesh(dataset / kReceiverModelName);
  const double diameter_m = 16.64;
  size_t frames = 0;
  for (size_t index = 0; index < test::kNearContactFrames; ++index) {
    const FrameSidecar sidecar = opened.Sidecar("frame", index);
    ASSERT_TRUE(sidecar.files.count("left_depth")) << "frame " << index << ": no depth truth";
    const DepthTruth truth =
        ReadDepthTruth(dataset / sidecar.files.at("left_depth").path, dataset / sidecar.files.at("left_mask").path);
    const Camera& left = sidecar.rig.left;
    const Eigen::Isometry3d cam_from_receiver =
        left.tanker_from_camera.inverse() * IsometryFromPose(sidecar.tanker_from_target);
    const DepthBuffer raster = RasterizeDepth(mesh, left.intrinsics, cam_from_receiver, sidecar.rig.near_m);
    size_t receiver = 0, agree = 0;
    for (int y = 0; y < truth.ids.rows; ++y) {
      for (int x = 0; x < truth.ids.cols; ++x) {
        if (truth.ids.at<uint8_t>(y, x) != kReceiverId) continue;
        ++receiver;
        agree += std::abs(raster.At(x, y) - truth.depth_m.at<float>(y, x)) < 0.001f ? 1 : 0;
      }
    }
    ASSERT_GT(receiver, 10000u) << "frame " << index;
    EXPECT_GT(static_cast<double>(agree) / static_cast<double>(receiver), 0.995) << "frame " << index;
    const VsdErrors e = VsdFromDepth(raster, raster, truth.depth_m, left.intrinsics, diameter_m);
    for (double error : e) EXPECT_EQ(error, 0.0) << "frame " << index;
    // One pixel of shift costs about the outline's share of the silhouette.
    Eigen::Isometry3d shifted = cam_from_receiver;
    shifted.translation().x() += cam_from_receiver.translation().z() / left.intrinsics.fx_px;
    const VsdErrors moved =
        ComputeVsd(mesh, left.intrinsics, shifted, cam_from_receiver, truth.depth_m, diameter_m, sidecar.rig.near_m);
    EXPECT_GT(moved[9], 0.005) << "frame " << index;
    EXPECT_LT(moved[9], 0.2) << "frame " << index;
    std::printf("frame %zu: %zu receiver pixels, %.4f agree within 1 mm, e_VSD after 1 px %.4f\n", index, receiver,
                static_cast<double>(agree) / static_cast<double>(receiver), moved[9]);
    ++frames;
  }
  EXPECT_EQ(frames, test::kNearContactFrames);
}

// A run over a dataset with depth truth scores AR_VSD and BOP's AR.
TEST(PipelineVsd, RunsOnDepthTruthScoreArVsd) {
  ASSERT_DATASETS();
  test::TempDir dir("pipeline-vsd");
  const test::CommandResult r = test::RunAnalyze("run " + Quote(SharedDatasets().near_contact) +
                                                 " --no-progress --frames 0:3 --out " + Quote(dir / "run"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::vector<FrameResult> frames = ReadFrameResults(dir / "run" / kFramesCsvName);
  ASSERT_EQ(frames.size(), 3u);
  for (const FrameResult& f : frames) {
    ASSERT_TRUE(f.bop_errors && f.bop_errors->vsd) << "frame " << f.frame;
    for (size_t t = 1; t < f.bop_errors->vsd->size(); ++t)
      EXPECT_LE((*f.bop_errors->vsd)[t], (*f.bop_errors->vsd)[t - 1]);
    EXPECT_LT(f.bop_errors->vsd->back(), 0.1) << "frame " << f.frame;  // region C: centimetres off
  }
  const nlohmann::json bop = ReadJsonFile(dir / "run" / kSummaryJsonName).at("models").at("shelled").at("C").at("bop");
  EXPECT_GT(bop.at("ar_vsd").get<double>(), 0.9);
  EXPECT_NEAR(
      bop.at("ar").get<double>(),
      (bop.at("ar_vsd").get<double>() + bop.at("ar_mssd").get<double>() + bop.at("ar_mspd").get<double>()) / 3.0,
      1e-12);
  EXPECT_NE(ReadFileBytes(dir / "run" / kSummaryMarkdownName).find("| AR VSD |"), std::string::npos);
}

}  // namespace
}  // namespace aar
