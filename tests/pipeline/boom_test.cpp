// The boom end to end: aar-render puts it in the scene for a flight path with
// the boom columns (its own id in the mask, its pose in the sidecar, its
// models and settings in the manifest) and leaves datasets without it as they
// were; aar-analyze reports the receiver fraction it hides and, by default on
// such a dataset, removes its pixels before re-projection. And the
// propellers: the default preset masks them on a dataset whose propellers turn.

#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include "aar/analyzer/analysis_run.h"
#include "aar/analyzer/frame_results.h"
#include "aar/dataset.h"
#include "aar/file_io.h"
#include "pipeline_support.h"

namespace aar {
namespace {

namespace fs = std::filesystem;
using test::Quote;
using test::RunAnalyze;
using test::SourcePath;
using test::TempDir;

// Frames 600 and 601: the contact hold, region C, the boom tracking the receptacle.
test::CommandResult Render(const fs::path& out, const std::string& path, const std::string& flags = "") {
  return test::RunCommand(
      "env -u SLURM_ARRAY_TASK_ID -u SLURM_ARRAY_TASK_COUNT " + Quote(test::RenderExe()) + " render " + Quote(out) +
      " --no-progress --msaa 1 --depth-right --frames 600:602 --flight-path " + Quote(SourcePath(path)) + " " + flags);
}

std::string Bytes(const fs::path& dataset, const std::string& relative) { return ReadFileBytes(dataset / relative); }

TEST(BoomPipeline, RenderedWithItsIdPoseAndModelsAndAbsentByDefault) {
  TempDir dir;
  const fs::path boom = dir / "boom", plain = dir / "plain", stowed = dir / "stowed";
  for (const auto& [out, path, flags] :
       {std::tuple{boom, "flightpaths/conops-boom.csv", ""}, std::tuple{plain, "flightpaths/conops.csv", ""},
        std::tuple{stowed, "flightpaths/conops.csv", "--boom"}}) {
    const test::CommandResult r = Render(out, path, flags);
    ASSERT_EQ(r.exit_code, 0) << r.output;
  }
  // With the boom columns: id 6 in the mask, the pose in the sidecar, the models and settings in the manifest.
  const Manifest with = ReadManifest(boom);
  EXPECT_EQ(with.json.at("frames").at("boom").at("mask_id"), kBoomMaskId);
  EXPECT_TRUE(with.files.contains(kBoomModelName) && with.files.contains(kBoomTubeModelName));
  EXPECT_EQ(Bytes(boom, kBoomModelName), ReadFileBytes(SourcePath("scenes/kc46_boom.glb")));
  const FrameSidecar sidecar = ReadSidecar(SidecarPath(boom, "frame", 600));
  ASSERT_TRUE(sidecar.boom.has_value());
  EXPECT_GT(sidecar.boom->pitch_deg, 30.0);
  EXPECT_TRUE(ReadJsonFile(SidecarPath(boom, "frame", 600)).at("boom").contains("tanker_from_boom"));
  for (const char* side : {"left", "right"}) {
    const cv::Mat ids =
        cv::imread((boom / ("frames/000600_" + std::string(side) + "_mask.png")).string(), cv::IMREAD_UNCHANGED);
    ASSERT_FALSE(ids.empty());
    EXPECT_GT(cv::countNonZero(ids == kBoomMaskId), 2000) << side;
    EXPECT_GT(cv::countNonZero(ids == 1), 10000) << side;  // the receiver, partly hidden
  }
  EXPECT_NE(Bytes(boom, "frames/000600_left.png"), Bytes(plain, "frames/000600_left.png"));

  // Without the columns or --boom: nothing of the boom anywhere.
  const Manifest without = ReadManifest(plain);
  EXPECT_FALSE(without.json.at("frames").contains("boom"));
  EXPECT_FALSE(without.json.at("inputs").contains("boom_model"));
  EXPECT_FALSE(fs::exists(plain / kBoomModelName));
  EXPECT_FALSE(ReadJsonFile(SidecarPath(plain, "frame", 600)).contains("boom"));

  // --boom on a 7-column path: the stowed boom is out of view, so every image,
  // depth, mask and silhouette has the bytes of the dataset without it; the
  // manifest and the sidecars record it.
  EXPECT_TRUE(ReadManifest(stowed).json.at("frames").contains("boom"));
  const FrameSidecar stowed_sidecar = ReadSidecar(SidecarPath(stowed, "frame", 601));
  ASSERT_TRUE(stowed_sidecar.boom.has_value());
  EXPECT_EQ(stowed_sidecar.boom->pitch_deg, 0.0);
  for (const auto& [name, ref] : stowed_sidecar.files) {
    EXPECT_EQ(ref.sha256, ReadSidecar(SidecarPath(plain, "frame", 601)).files.at(name).sha256) << name;
  }
}

TEST(BoomPipeline, AnalyzerReportsOcclusionAndMaskingRemovesBoomPoints) {
  TempDir dir;
  const fs::path boom = dir / "boom", plain = dir / "plain";
  ASSERT_EQ(Render(boom, "flightpaths/conops-boom.csv").exit_code, 0);
  ASSERT_EQ(Render(plain, "flightpaths/conops.csv").exit_code, 0);
  const auto analyze = [&](const fs::path& dataset, const fs::path& out, const std::string& flags) {
    return RunAnalyze("run " + Quote(dataset) + " --no-progress --frames 600:602 --calibration " +
                      Quote(dataset / kIdealCalibrationName) + " --out " + Quote(out) + " " + flags);
  };
  test::CommandResult r = analyze(boom, dir / "unmasked", "--no-mask-boom");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = analyze(boom, dir / "masked", "--mask-boom");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = analyze(boom, dir / "default", "");  // the default preset masks the boom of a dataset that has one
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto without_timing = [](const fs::path& run) {
    std::vector<FrameResult> frames = ReadFrameResults(run / kFramesCsvName);
    for (FrameResult& f : frames) f.times = StageTimes{};
    return FormatFrameResults(frames);
  };
  EXPECT_EQ(without_timing(dir / "default"), without_timing(dir / "masked"));
  const std::vector<FrameResult> unmasked = ReadFrameResults(dir / "unmasked" / kFramesCsvName);
  const std::vector<FrameResult> masked = ReadFrameResults(dir / "masked" / kFramesCsvName);
  ASSERT_EQ(unmasked.size(), 2u);
  ASSERT_EQ(masked.size(), 2u);
  for (size_t i = 0; i < 2; ++i) {
    ASSERT_TRUE(unmasked[i].receiver_occluded_fraction.has_value());
    EXPECT_GT(*unmasked[i].receiver_occluded_fraction, 0.02);
    EXPECT_LT(*unmasked[i].receiver_occluded_fraction, 0.5);
    EXPECT_EQ(masked[i].receiver_occluded_fraction, unmasked[i].receiver_occluded_fraction);
    // Sensed points off the receiver (on the boom, by the depth truth) go with the masking.
    std::printf("frame %zu: occluded %.4f, points off the receiver %zu unmasked, %zu masked\n", unmasked[i].frame,
                *unmasked[i].receiver_occluded_fraction, unmasked[i].stereo_truth.off_receiver,
                masked[i].stereo_truth.off_receiver);
    EXPECT_GT(unmasked[i].stereo_truth.off_receiver, 50u);
    EXPECT_LT(masked[i].stereo_truth.off_receiver * 10, unmasked[i].stereo_truth.off_receiver);
  }
  EXPECT_TRUE(ReadJsonFile(dir / "masked" / kRunJsonName).at("options").contains("boom_mask"));
  EXPECT_FALSE(ReadJsonFile(dir / "unmasked" / kRunJsonName).at("options").contains("boom_mask"));

  // Without the boom: no occlusion column, no mask by default, and --mask-boom is refused.
  r = analyze(plain, dir / "plain-run", "");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_FALSE(ReadJsonFile(dir / "plain-run" / kRunJsonName).at("options").contains("boom_mask"));
  EXPECT_EQ(ReadFileBytes(dir / "plain-run" / kFramesCsvName).find("receiver_occluded_fraction"), std::string::npos);
  r = analyze(plain, dir / "plain-masked", "--mask-boom");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("--mask-boom: "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("has no boom"), std::string::npos) << r.output;
}

// Frames 600 and 601 with the propellers turning (blurred over a 4 ms exposure): the discs pull the estimate
// forward (x errors of +0.16 and +0.24 m unmasked), and the default masks them.
TEST(PropellerPipeline, TheDefaultMasksTurningPropellers) {
  TempDir dir;
  const fs::path propellers = dir / "propellers";
  ASSERT_EQ(Render(propellers, "flightpaths/conops.csv", "--propellers 1700 --shutter-ms 4").exit_code, 0);
  const auto analyze = [&](const fs::path& out, const std::string& flags) {
    return RunAnalyze("run " + Quote(propellers) + " --no-progress --frames 600:602 --calibration " +
                      Quote(propellers / kIdealCalibrationName) + " --out " + Quote(out) + " " + flags);
  };
  test::CommandResult r = analyze(dir / "default", "");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = analyze(dir / "unmasked", "--no-mask-propellers");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = analyze(dir / "thesis", "--preset thesis");  // the thesis's pipeline stays as it was
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(ReadJsonFile(dir / "default" / kRunJsonName).at("options").contains("propeller_mask"));
  EXPECT_FALSE(ReadJsonFile(dir / "unmasked" / kRunJsonName).at("options").contains("propeller_mask"));
  EXPECT_FALSE(ReadJsonFile(dir / "thesis" / kRunJsonName).at("options").contains("propeller_mask"));
  const std::vector<FrameResult> masked = ReadFrameResults(dir / "default" / kFramesCsvName);
  const std::vector<FrameResult> unmasked = ReadFrameResults(dir / "unmasked" / kFramesCsvName);
  ASSERT_EQ(masked.size(), 2u);
  ASSERT_EQ(unmasked.size(), 2u);
  for (size_t i = 0; i < 2; ++i) {
    ASSERT_TRUE(masked[i].ok() && unmasked[i].ok()) << masked[i].status << " / " << unmasked[i].status;
    std::printf("frame %zu: x error %.3f m masked, %.3f m unmasked\n", masked[i].frame, masked[i].error[0],
                unmasked[i].error[0]);
    EXPECT_GT(std::abs(unmasked[i].error[0]), 0.1);
    EXPECT_LT(std::abs(masked[i].error[0]), 0.6 * std::abs(unmasked[i].error[0]));
    // The depth truth's count of the points on the blades (the same cloud both ways), and what each kept.
    const StereoTruthStats &m = masked[i].stereo_truth, &u = unmasked[i].stereo_truth;
    std::printf("frame %zu: %zu of %zu points on the blades; kept %zu masked, %zu unmasked\n", masked[i].frame,
                u.on_propellers, u.points, m.propellers_kept, u.propellers_kept);
    EXPECT_EQ(m.on_propellers, u.on_propellers);
    EXPECT_GT(u.on_propellers, u.points / 100);
    EXPECT_EQ(u.propellers_kept, u.on_propellers);
    EXPECT_LT(m.propellers_kept, m.on_propellers / 10 + 1);
  }
}

}  // namespace
}  // namespace aar
