// Bad input to aar-analyze, through the executable. Problems that make a run
// impossible (no manifest, unreadable calibration, too few board corners):
// one clear message naming the file and the reason, a non-zero exit and no
// output folder. Problems of single frames (missing, undecodable or changed
// images, malformed sidecars, receiver out of view): recorded in the frame's
// status, counted as failed, and the run goes on and exits 0.

#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include "aar/analyzer/analysis_run.h"
#include "aar/analyzer/pose_statistics.h"
#include "aar/dataset.h"
#include "aar/file_io.h"
#include "pipeline_support.h"

namespace aar {
namespace {

namespace fs = std::filesystem;
using test::Quote;
using test::RunAnalyze;
using test::SharedDatasets;
using test::TempDir;

bool Contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// A fatal error: non-zero exit, one line naming `names` (all of them), no output folder.
void ExpectCleanFailure(const test::CommandResult& r, const std::vector<std::string>& names, const fs::path& out) {
  EXPECT_NE(r.exit_code, 0) << r.output;
  EXPECT_EQ(test::CountLines(r.output), 1u) << r.output;
  EXPECT_TRUE(Contains(r.output, "aar-analyze: error: ")) << r.output;
  for (const std::string& name : names)
    EXPECT_TRUE(Contains(r.output, name)) << "expected '" << name << "' in: " << r.output;
  EXPECT_FALSE(fs::exists(out)) << out << " was created";
}

TEST(AnalyzeBadInput, NoManifestFailsBeforeWritingOutput) {
  TempDir dir("analyze-bad-manifest");
  const fs::path dataset = dir / "not-a-dataset";
  fs::create_directories(dataset / "frames");
  WriteFileAtomic(dataset / "rig.json", ReadFileBytes(test::SourcePath("scenes/rig.json")));
  const fs::path out = dir / "out";
  ExpectCleanFailure(RunAnalyze("run " + Quote(dataset) + " --model shelled --no-progress --out " + Quote(out)),
                     {(dataset / kManifestName).string(), "no manifest"}, out);
  ExpectCleanFailure(RunAnalyze("calibrate " + Quote(dataset) + " --out " + Quote(out)),
                     {(dataset / kManifestName).string(), "no manifest"}, out);
}

TEST(AnalyzeBadInput, UnreadableCalibrationFailsBeforeWritingOutput) {
  ASSERT_DATASETS();
  TempDir dir("analyze-bad-calibration");
  constexpr char kGarbage[] = "this is not a calibration\0\x01\xff{[";
  WriteFileAtomic(dir / "garbage.yaml", std::string(kGarbage, sizeof(kGarbage) - 1));
  WriteFileAtomic(dir / "no-matrices.yaml", "%YAML:1.0\n---\nimage_size: [ 1024, 768 ]\n");
  const std::vector<std::pair<std::string, std::string>> cases = {{"garbage.yaml", "cannot parse calibration file"},
                                                                  {"missing.yaml", "calibration file not found"},
                                                                  {"no-matrices.yaml", "missing node M1"}};
  for (const auto& [name, reason] : cases) {
    SCOPED_TRACE(name);
    const fs::path out = dir / ("out-" + name);
    ExpectCleanFailure(
        RunAnalyze("run " + Quote(SharedDatasets().near_contact) + " --model shelled --no-progress --calibration " +
                   Quote(dir / name) + " --out " + Quote(out)),
        {(dir / name).string(), reason}, out);
  }
}

TEST(AnalyzeBadInput, TooFewBoardCornersFailsCalibration) {
  ASSERT_DATASETS();
  TempDir dir("analyze-bad-corners");
  const fs::path dataset = dir / "dataset";
  test::CopyDataset(SharedDatasets().near_contact, dataset);
  // 10 of the 12 left calibration images become plain sky of the same size.
  const cv::Mat first = cv::imread((dataset / "calib/000000_left.png").string(), cv::IMREAD_COLOR);
  ASSERT_FALSE(first.empty());
  const cv::Mat sky(first.size(), first.type(), cv::Scalar(first.at<cv::Vec3b>(0, 0)));
  for (size_t i = 2; i < 12; ++i) {
    ASSERT_TRUE(cv::imwrite((dataset / kCalibDir / (FrameStem(i) + "_left.png")).string(), sky));
  }
  const std::vector<std::string> names = {dataset.string(), "only 2 of 12 calibration pairs",
                                          "calib/000002_left.png: found no"};
  const fs::path out = dir / "out";
  ExpectCleanFailure(RunAnalyze("calibrate " + Quote(dataset) + " --out " + Quote(out)), names, out);
  // A run without --calibration calibrates first: the same failure, before any output.
  ExpectCleanFailure(RunAnalyze("run " + Quote(dataset) + " --model shelled --no-progress --out " + Quote(out)), names,
                     out);
}

// Sets the SHA-256 of `file` in its frame's sidecar and in the manifest (and
// the sidecar's own), as if the dataset had been written with that content.
void RehashFrameFile(const fs::path& dataset, size_t frame, const std::string& side) {
  const fs::path sidecar = SidecarPath(dataset, "frame", frame);
  nlohmann::json s = ReadJsonFile(sidecar);
  const std::string file = s.at("files").at(side).at("path").get<std::string>();
  s["files"][side]["sha256"] = Sha256File(dataset / file);
  WriteJsonFile(sidecar, s);
  nlohmann::json manifest = ReadJsonFile(dataset / kManifestName);
  manifest["files"][file] = Sha256File(dataset / file);
  manifest["files"][fs::relative(sidecar, dataset).generic_string()] = Sha256File(sidecar);
  WriteJsonFile(dataset / kManifestName, manifest);
}

TEST(AnalyzeBadInput, BrokenFramesAreRecordedAndTheRunGoesOn) {
  ASSERT_DATASETS();
  ASSERT_GE(test::kNearContactFrames, 7u);
  TempDir dir("analyze-bad-frames");
  const fs::path dataset = dir / "dataset";
  test::CopyDataset(SharedDatasets().near_contact, dataset);
  const fs::path frames = dataset / kFramesDir;
  const std::string garbage = "\x89PNG\r\n\x1a\n but not really a PNG image at all";
  // (a) a right image deleted
  fs::remove(frames / "000000_right.png");
  // (b) a left image replaced by bytes that are no PNG, its hashes updated: only decoding can tell
  WriteFileAtomic(frames / "000001_left.png", garbage);
  RehashFrameFile(dataset, 1, "left");
  // (c) a sidecar that is no JSON
  WriteFileAtomic(frames / "000002.json", "{\"schema\": \"aar-frame/1\", \"kind\": ");
  // (d) one byte of a left image changed
  std::string bytes = ReadFileBytes(frames / "000003_left.png");
  bytes[bytes.size() / 2] = static_cast<char>(bytes[bytes.size() / 2] ^ 0x01);
  WriteFileAtomic(frames / "000003_left.png", bytes);
  // (e) a right image replaced by garbage, hashes not updated: the hash check catches it before decoding
  WriteFileAtomic(frames / "000004_right.png", garbage);

  const fs::path out = dir / "out";
  const test::CommandResult r = RunAnalyze("run " + Quote(dataset) + " --model shelled --no-progress --calibration " +
                                           Quote(dataset / kIdealCalibrationName) + " --out " + Quote(out));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(Contains(r.output, std::to_string(test::kNearContactFrames) + " frames analyzed, 5 not measured"))
      << r.output;

  const std::vector<FrameResult> results = ReadFrameResults(out / kFramesCsvName);
  ASSERT_EQ(results.size(), test::kNearContactFrames);
  const std::vector<std::vector<std::string>> expected = {{"frames/000000_right.png", "missing"},
                                                          {"frames/000001_left.png", "cannot decode"},
                                                          {"frames/000002.json", "not valid JSON"},
                                                          {"frames/000003_left.png", "SHA-256"},
                                                          {"frames/000004_right.png", "SHA-256"}};
  for (const FrameResult& f : results) {
    if (f.frame < expected.size()) {
      for (const std::string& part : expected[f.frame]) {
        EXPECT_TRUE(Contains(f.status, part)) << "frame " << f.frame << ": expected '" << part << "' in: " << f.status;
      }
    } else {
      EXPECT_EQ(f.status, "ok") << "frame " << f.frame;
    }
    EXPECT_EQ(f.frame, static_cast<size_t>(&f - results.data()));
  }
  const nlohmann::json all = ReadJsonFile(out / kSummaryJsonName).at("models").at("shelled").at("all");
  EXPECT_EQ(all.at("frames").get<size_t>(), test::kNearContactFrames);
  EXPECT_EQ(all.at("failed").get<size_t>(), 5u);
  EXPECT_EQ(all.at("ok").get<size_t>(), test::kNearContactFrames - 5);
}

TEST(AnalyzeBadInput, ReceiverOutOfViewIsRecordedAndTheRunGoesOn) {
  ASSERT_DATASETS();
  TempDir dir("analyze-out-of-view");
  const fs::path dataset = SharedDatasets().out_of_view;
  const fs::path out = dir / "out";
  const test::CommandResult r = RunAnalyze("run " + Quote(dataset) + " --model shelled --no-progress --calibration " +
                                           Quote(dataset / kIdealCalibrationName) + " --out " + Quote(out));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::vector<FrameResult> results = ReadFrameResults(out / kFramesCsvName);
  ASSERT_EQ(results.size(), 2u);
  EXPECT_EQ(results[0].status, "ok");
  EXPECT_TRUE(Contains(results[1].status, "frames/000001_left.png")) << results[1].status;
  EXPECT_TRUE(Contains(results[1].status, "sensed points")) << results[1].status;
  EXPECT_TRUE(Contains(results[1].status, "out of view")) << results[1].status;
  EXPECT_EQ(results[1].sensed_points, 0u);
  const nlohmann::json all = ReadJsonFile(out / kSummaryJsonName).at("models").at("shelled").at("all");
  EXPECT_EQ(all.at("ok").get<size_t>(), 1u);
  EXPECT_EQ(all.at("failed").get<size_t>(), 1u);
}

}  // namespace
}  // namespace aar
