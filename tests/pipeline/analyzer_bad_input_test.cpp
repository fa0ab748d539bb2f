// Bad input to aar-analyze, through the executable. Problems that make a run
// impossible (no manifest, unreadable calibration, too few board corners):
// one clear message naming the file and the reason, a non-zero exit and no
// output folder. Problems of single frames (missing, undecodable or changed
// images, malformed sidecars, receiver out of view): recorded in the frame's
// status, counted as failed, and the run goes on and exits 0.

#include <gtest/gtest.h>

#include <functional>
#include <opencv2/imgcodecs.hpp>
#include <tuple>

#include "aar/analyzer/analysis_run.h"
#include "aar/analyzer/pose_statistics.h"
#include "aar/dataset.h"
#include "aar/file_io.h"
#include "aar/folder_lock.h"
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

TEST(AnalyzeBadInput, UnknownLensModelFailsBeforeWritingOutput) {
  ASSERT_DATASETS();
  TempDir dir("analyze-bad-lens-model");
  const fs::path out = dir / "out";
  ExpectCleanFailure(
      RunAnalyze("calibrate " + Quote(SharedDatasets().near_contact) + " --distortion fisheye --out " + Quote(out)),
      {"--distortion 'fisheye': expected auto, pinhole, brown-conrady or brown-conrady-k3"}, out);
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

// Sets the SHA-256 of a pair's `side` file in its sidecar and in the manifest
// (and the sidecar's own), as if the dataset had been written with that content.
void RehashFile(const fs::path& dataset, const std::string& kind, size_t index, const std::string& side) {
  const fs::path sidecar = SidecarPath(dataset, kind, index);
  nlohmann::json s = ReadJsonFile(sidecar);
  const std::string file = s.at("files").at(side).at("path").get<std::string>();
  s["files"][side]["sha256"] = Sha256File(dataset / file);
  WriteJsonFile(sidecar, s);
  nlohmann::json manifest = ReadJsonFile(dataset / kManifestName);
  manifest["files"][file] = Sha256File(dataset / file);
  manifest["files"][fs::relative(sidecar, dataset).generic_string()] = Sha256File(sidecar);
  WriteJsonFile(dataset / kManifestName, manifest);
}

TEST(AnalyzeBadInput, TooFewBoardCornersFailsCalibration) {
  ASSERT_DATASETS();
  TempDir dir("analyze-bad-corners");
  const fs::path dataset = dir / "dataset";
  test::CopyDataset(SharedDatasets().near_contact, dataset);
  // 10 of the 12 left calibration images become plain sky of the same size (as rendered: the hashes agree).
  const cv::Mat first = cv::imread((dataset / "calib/000000_left.png").string(), cv::IMREAD_COLOR);
  ASSERT_FALSE(first.empty());
  const cv::Mat sky(first.size(), first.type(), cv::Scalar(first.at<cv::Vec3b>(0, 0)));
  for (size_t i = 2; i < 12; ++i) {
    ASSERT_TRUE(cv::imwrite((dataset / kCalibDir / (FrameStem(i) + "_left.png")).string(), sky));
    RehashFile(dataset, "calib", i, "left");
  }
  const std::vector<std::string> names = {dataset.string(), "only 2 of 12 calibration pairs",
                                          "calib/000002_left.png: found no"};
  const fs::path out = dir / "out";
  ExpectCleanFailure(RunAnalyze("calibrate " + Quote(dataset) + " --out " + Quote(out)), names, out);
  // A run without --calibration calibrates first: the same failure, before any output.
  ExpectCleanFailure(RunAnalyze("run " + Quote(dataset) + " --model shelled --no-progress --out " + Quote(out)), names,
                     out);
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
  // (b) a left image replaced by bytes that are no PNG, its hashes updated: only reading it can tell
  WriteFileAtomic(frames / "000001_left.png", garbage);
  RehashFile(dataset, "frame", 1, "left");
  // (c) a sidecar that is no JSON, its hash in the manifest updated
  WriteFileAtomic(frames / "000002.json", "{\"schema\": \"aar-frame/1\", \"kind\": ");
  nlohmann::json manifest = ReadJsonFile(dataset / kManifestName);
  manifest["files"]["frames/000002.json"] = Sha256File(frames / "000002.json");
  WriteJsonFile(dataset / kManifestName, manifest);
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
                                                          {"frames/000001_left.png", "not a whole PNG file"},
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

namespace aar {
namespace {

// Robustness of runs, merges and inputs (issue 10): each refusal is one line
// naming the file, a non-zero exit, and nothing written.
class AnalyzeRobustness : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_DATASETS();
    dataset_ = dir_ / "dataset";
    test::CopyDataset(SharedDatasets().out_of_view, dataset_);
  }
  std::string RunArgs(const fs::path& out, const std::string& extra = "") const {
    return "run " + Quote(dataset_) + " --model shelled --no-progress --calibration " +
           Quote(dataset_ / kIdealCalibrationName) + " --out " + Quote(out) + " " + extra;
  }
  void EditManifest(const std::function<void(nlohmann::json&)>& edit) const {
    nlohmann::json manifest = ReadJsonFile(dataset_ / kManifestName);
    edit(manifest);
    WriteJsonFile(dataset_ / kManifestName, manifest);
  }
  TempDir dir_{"analyze-robustness"};
  fs::path dataset_;
};

TEST_F(AnalyzeRobustness, ChangedInputCopiesAreRefused) {
  const std::vector<std::pair<std::string, std::string>> swaps = {{kReceiverModelName, "scenes/kc46.glb"},
                                                                  {kRigName, ""}};
  for (const auto& [name, replacement] : swaps) {
    SCOPED_TRACE(name);
    const std::string original = ReadFileBytes(dataset_ / name);
    std::string changed = replacement.empty() ? original : ReadFileBytes(test::SourcePath(replacement));
    if (replacement.empty()) changed.replace(changed.find("\"near_m\": 0.5"), 13, "\"near_m\": 0.6");
    WriteFileAtomic(dataset_ / name, changed);
    const fs::path out = dir_ / ("out-" + name);
    ExpectCleanFailure(RunAnalyze(RunArgs(out)), {(dataset_ / name).string(), "SHA-256 differs from manifest.json's"},
                       out);
    WriteFileAtomic(dataset_ / name, original);
  }
}

TEST_F(AnalyzeRobustness, ManifestsThatWouldSkipChecksAreRefused) {
  const std::vector<std::tuple<std::string, std::function<void(nlohmann::json&)>, std::string>> cases = {
      {"files-array", [](nlohmann::json& m) { m["files"] = nlohmann::json::array(); }, "'files' must map"},
      {"files-empty", [](nlohmann::json& m) { m["files"] = nlohmann::json::object(); }, "complete, but 'files'"},
      {"frame-unlisted", [](nlohmann::json& m) { m["files"].erase("frames/000001.json"); },
       "does not list frames/000001.json"},
      {"huge-count", [](nlohmann::json& m) { m["frames"]["count"] = 1000000000000000ull; }, "above 10000000"},
      {"count-differs", [](nlohmann::json& m) { m["frames"]["count"] = 3; }, "differs from the 2 samples"},
  };
  const std::string original = ReadFileBytes(dataset_ / kManifestName);
  for (const auto& [name, edit, reason] : cases) {
    SCOPED_TRACE(name);
    EditManifest(edit);
    const fs::path out = dir_ / ("out-" + name);
    ExpectCleanFailure(RunAnalyze(RunArgs(out)), {(dataset_ / kManifestName).string(), reason}, out);
    WriteFileAtomic(dataset_ / kManifestName, original);
  }
  const fs::path out = dir_ / "out-past-end";
  ExpectCleanFailure(RunAnalyze(RunArgs(out, "--frames 5:9")), {"--frames starts at 5, past the last frame"}, out);
}

TEST_F(AnalyzeRobustness, OutputFolderInUseIsRefused) {
  const fs::path out = dir_ / "out";
  fs::create_directories(out);
  const FileLock held = LockOutputFolder(out);
  const test::CommandResult r = RunAnalyze(RunArgs(out));
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_EQ(test::CountLines(r.output), 1u) << r.output;
  EXPECT_TRUE(Contains(r.output, out.string() + ": output folder in use by another run")) << r.output;
  EXPECT_FALSE(fs::exists(out / kRunJsonName));
}

TEST_F(AnalyzeRobustness, ShardsGetDistinctDefaultOutputFolders) {
  for (const char* task : {"0", "1"}) {
    const std::string command = "cd " + Quote(dir_.path()) + " && env SLURM_ARRAY_TASK_ID=" + task +
                                " SLURM_ARRAY_TASK_COUNT=2 SLURM_ARRAY_TASK_MIN=0 SLURM_ARRAY_TASK_MAX=1 " +
                                Quote(test::AnalyzeExe()) + " run " + Quote(dataset_) +
                                " --model shelled --no-progress --calibration " +
                                Quote(dataset_ / kIdealCalibrationName);
    const test::CommandResult r = test::RunCommand(command);
    ASSERT_EQ(r.exit_code, 0) << r.output;
  }
  for (const char* shard : {"0", "1"}) {
    const fs::path out = dir_ / "results" / ("dataset-shelled-shard" + std::string(shard) + "of2");
    ASSERT_TRUE(fs::is_regular_file(out / kFramesCsvName)) << out;
    EXPECT_EQ(ReadFrameResults(out / kFramesCsvName).size(), 1u);
  }
}

TEST_F(AnalyzeRobustness, MergeRefusesUnfinishedOrForeignShardsAndItsOwnInputs) {
  const fs::path s0 = dir_ / "s0", s1 = dir_ / "s1";
  ASSERT_EQ(RunAnalyze(RunArgs(s0, "--shard 0/2")).exit_code, 0);
  ASSERT_EQ(RunAnalyze(RunArgs(s1, "--shard 1/2")).exit_code, 0);
  const std::string s1_frames = ReadFileBytes(s1 / kFramesCsvName);

  const auto merge = [&](const fs::path& out) {
    return RunAnalyze("merge " + Quote(s0) + " " + Quote(s1) + " --out " + Quote(out));
  };
  // --out is a shard: refused before anything is written.
  const test::CommandResult into_shard = RunAnalyze("merge " + Quote(s0) + " " + Quote(s1) + " --out " + Quote(s1));
  EXPECT_EQ(into_shard.exit_code, 1) << into_shard.output;
  EXPECT_TRUE(Contains(into_shard.output, "--out is one of the shard folders")) << into_shard.output;
  EXPECT_EQ(ReadFileBytes(s1 / kFramesCsvName), s1_frames);
  // An incomplete run.json names its file.
  const std::string run = ReadFileBytes(s1 / kRunJsonName);
  nlohmann::json partial = nlohmann::json::parse(run);
  partial.erase("options");
  WriteJsonFile(s1 / kRunJsonName, partial);
  ExpectCleanFailure(merge(dir_ / "m1"), {(s1 / kRunJsonName).string(), "incomplete run.json (no 'options')"},
                     dir_ / "m1");
  // A folder without run.json is no finished run.
  fs::remove(s1 / kRunJsonName);
  ExpectCleanFailure(merge(dir_ / "m2"), {(s1 / kRunJsonName).string(), "the run did not finish"}, dir_ / "m2");
  // frames.csv of another run beside this run.json.
  WriteFileAtomic(s1 / kRunJsonName, run);
  WriteFileAtomic(s1 / kFramesCsvName, ReadFileBytes(s0 / kFramesCsvName) + s1_frames.substr(s1_frames.find('\n') + 1));
  ExpectCleanFailure(merge(dir_ / "m3"), {(s1 / kFramesCsvName).string(), "but run.json says 1 were analyzed"},
                     dir_ / "m3");
  WriteFileAtomic(s1 / kFramesCsvName, s1_frames);
  const test::CommandResult ok = merge(dir_ / "m4");
  EXPECT_EQ(ok.exit_code, 0) << ok.output;
  EXPECT_EQ(ReadFrameResults(dir_ / "m4" / kFramesCsvName).size(), 2u);
}

TEST_F(AnalyzeRobustness, RerunIntoAUsedFolderRemovesLeftovers) {
  const fs::path out = dir_ / "out";
  ASSERT_EQ(RunAnalyze(RunArgs(out)).exit_code, 0);
  WriteFileAtomic(out / ".tmp999.frames.csv", "partial");
  ASSERT_EQ(RunAnalyze(RunArgs(out)).exit_code, 0);
  EXPECT_FALSE(fs::exists(out / ".tmp999.frames.csv"));
  EXPECT_TRUE(fs::is_regular_file(out / kRunJsonName));
}

TEST(AnalyzeCommandLine, HugeReferencePointCountIsRefusedByName) {
  TempDir dir("analyze-points");
  const fs::path out = dir / "r.ply";
  const test::CommandResult r = RunAnalyze("reference --model full --points 100000000000000 --out " + Quote(out));
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_EQ(test::CountLines(r.output), 1u) << r.output;
  EXPECT_TRUE(Contains(r.output, "num_points (--points) 100000000000000 must be 1 to 10000000")) << r.output;
  EXPECT_FALSE(fs::exists(out));
}

TEST(AnalyzeCommandLine, VersionNamesTheReleaseAndTheBuild) {
  const test::CommandResult r = RunAnalyze("--version");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(r.output.rfind(std::string("aar-analyze ") + AAR_TEST_VERSION + " (git ", 0), 0u) << r.output;
}

}  // namespace
}  // namespace aar
