// Resuming into an existing dataset: a refused resume (other flight path, rig
// or receiver, or an optional setting added or left out) changes no file of
// the dataset; a resume with nothing to render touches no file; frames mixed
// by hand are found; a dataset without manifest is refused; leftovers of
// interrupted writes are removed; an error of the writer thread stops the run
// and a rerun resumes; two renders with different settings started together:
// exactly one is accepted.

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <chrono>
#include <map>
#include <string>

#include "../test_support.h"
#include "aar/dataset.h"
#include "aar/file_io.h"

namespace aar {
namespace {

namespace fs = std::filesystem;
using test::RunCommand;
using test::SourcePath;
using test::TempDir;

struct Inputs {
  std::string rig = SourcePath("scenes/rig.json").string();
  std::string receiver = SourcePath("scenes/c12.glb").string();
  std::string flight_path = SourcePath("flightpaths/conops.csv").string();
  std::string extra;
};

std::string RenderCommand(const fs::path& out, const Inputs& in) {
  return "env -u SLURM_ARRAY_TASK_ID -u SLURM_ARRAY_TASK_COUNT " + test::BinaryPath("renderer/aar-render").string() +
         " render " + out.string() + " --no-progress --frames 600:601 --msaa 1 --rig " + in.rig + " --receiver " +
         in.receiver + " --tanker " + SourcePath("scenes/kc46.glb").string() + " --flight-path " + in.flight_path +
         " " + in.extra;
}

// Every file of the dataset (relative path -> content).
std::map<std::string, std::string> Snapshot(const fs::path& dataset) {
  std::map<std::string, std::string> files;
  for (const auto& entry : fs::recursive_directory_iterator(dataset)) {
    if (entry.is_regular_file()) files[fs::relative(entry.path(), dataset).string()] = ReadFileBytes(entry.path());
  }
  return files;
}

// Every file's modification time (relative path -> nanoseconds).
std::map<std::string, long long> Times(const fs::path& dataset) {
  std::map<std::string, long long> times;
  for (const auto& entry : fs::recursive_directory_iterator(dataset)) {
    times[fs::relative(entry.path(), dataset).string()] =
        std::chrono::duration_cast<std::chrono::nanoseconds>(entry.last_write_time().time_since_epoch()).count();
  }
  return times;
}

// One rendered frame, shared by the tests of this file (rendered once per process).
class RenderResume : public ::testing::Test {
 protected:
  void SetUp() override {
    dataset_ = dir_ / "dataset";
    const test::CommandResult r = RunCommand(RenderCommand(dataset_, Inputs{}));
    ASSERT_EQ(r.exit_code, 0) << r.output;
  }
  TempDir dir_;
  fs::path dataset_;
};

TEST_F(RenderResume, RefusedResumeChangesNoFile) {
  std::string csv = ReadFileBytes(SourcePath("flightpaths/conops.csv"));
  csv.replace(csv.rfind('\n', csv.size() - 2) + 1, 1, "9");  // the last sample's time changes
  WriteFileAtomic(dir_ / "other.csv", csv);
  std::string rig = ReadFileBytes(SourcePath("scenes/rig.json"));
  rig.replace(rig.find("\"near_m\": 0.5"), 13, "\"near_m\": 0.6");
  WriteFileAtomic(dir_ / "other-rig.json", rig);
  Inputs other_path, other_rig, other_receiver;
  other_path.flight_path = (dir_ / "other.csv").string();
  other_rig.rig = (dir_ / "other-rig.json").string();
  other_receiver.receiver = SourcePath("scenes/kc46.glb").string();

  const auto before = Snapshot(dataset_);
  for (const auto& [inputs, key] : {std::pair{other_path, "inputs.flight_path.sha256"},
                                    {other_rig, "inputs.rig.sha256"},
                                    {other_receiver, "inputs.receiver_model.sha256"}}) {
    SCOPED_TRACE(key);
    const test::CommandResult r = RunCommand(RenderCommand(dataset_, inputs));
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_NE(r.output.find(std::string("made with other settings (") + key), std::string::npos) << r.output;
    EXPECT_EQ(Snapshot(dataset_), before) << "a refused resume changed the dataset";
  }
}

// The settings that only some datasets have (a background, the boom, turning
// propellers, a shutter) compare both ways: adding one on a resume, or
// leaving out one the dataset has, is refused and changes nothing.
TEST_F(RenderResume, AnOptionalSettingAddedOrLeftOutIsRefused) {
  const auto before = Snapshot(dataset_);
  for (const auto& [extra, difference] : {std::pair{"--background sky", "frames.background: was absent, now {"},
                                          {"--boom", "frames.boom: was absent, now {"},
                                          {"--propellers 1200", "frames.propellers: was absent, now {"},
                                          {"--shutter-ms 4 --time-samples 2", "frames.exposure: was absent, now {"}}) {
    SCOPED_TRACE(extra);
    Inputs with;
    with.extra = extra;
    const test::CommandResult r = RunCommand(RenderCommand(dataset_, with));
    EXPECT_EQ(r.exit_code, 1) << r.output;
    EXPECT_NE(r.output.find(std::string("made with other settings (") + difference), std::string::npos) << r.output;
    EXPECT_EQ(Snapshot(dataset_), before) << "a refused resume changed the dataset";
  }
  // The other way: a dataset with the sky, resumed without it.
  const fs::path sky = dir_ / "sky";
  Inputs with_sky;
  with_sky.extra = "--background sky";
  ASSERT_EQ(RunCommand(RenderCommand(sky, with_sky)).exit_code, 0);
  const auto sky_before = Snapshot(sky);
  const test::CommandResult r = RunCommand(RenderCommand(sky, Inputs{}));
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("made with other settings (frames.background: was {"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("}, now absent)"), std::string::npos) << r.output;
  EXPECT_EQ(Snapshot(sky), sky_before);

  // Frames mixed by hand (the sky's frame copied over this one) are found:
  // finalize refuses them, and the analyzer's frame check names the sidecar.
  for (const char* name : {"000600.json", "000600_left.png", "000600_right.png"}) {
    fs::copy_file(sky / "frames" / name, dataset_ / "frames" / name, fs::copy_options::overwrite_existing);
  }
  const test::CommandResult finalize =
      RunCommand(test::BinaryPath("renderer/aar-render").string() + " finalize " + dataset_.string());
  EXPECT_EQ(finalize.exit_code, 1) << finalize.output;
  EXPECT_NE(finalize.output.find((dataset_ / "frames" / "000600.json").string() +
                                 ": rendered with other settings than manifest.json records"),
            std::string::npos)
      << finalize.output;
  const Manifest manifest = ReadManifest(dataset_);
  EXPECT_FALSE(SidecarVerified(dataset_, SidecarPath(dataset_, "frame", 600), manifest.frame_settings_sha256));
}

// A resume with nothing left to render leaves every file as it was, time
// stamps included.
TEST_F(RenderResume, AResumeThatRendersNothingTouchesNoFile) {
  const auto before = Snapshot(dataset_);
  const auto times = Times(dataset_);
  const test::CommandResult r = RunCommand(RenderCommand(dataset_, Inputs{}));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("0 pairs rendered, 1 already complete"), std::string::npos) << r.output;
  EXPECT_EQ(Snapshot(dataset_), before);
  EXPECT_EQ(Times(dataset_), times);
}

TEST_F(RenderResume, DatasetWithoutManifestIsRefused) {
  fs::remove(dataset_ / kManifestName);
  const auto before = Snapshot(dataset_);
  const test::CommandResult r = RunCommand(RenderCommand(dataset_, Inputs{}));
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("manifest.json: missing, but"), std::string::npos) << r.output;
  EXPECT_EQ(Snapshot(dataset_), before);
}

TEST_F(RenderResume, ResumeRemovesTemporariesOfInterruptedWrites) {
  WriteFileAtomic(dataset_ / "frames" / ".tmp4242.000600_left.png", "half a PNG");
  WriteFileAtomic(dataset_ / ".tmp4242.manifest.json", "{");
  const test::CommandResult r = RunCommand(RenderCommand(dataset_, Inputs{}));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("0 pairs rendered, 1 already complete"), std::string::npos) << r.output;
  for (const auto& [name, content] : Snapshot(dataset_)) {
    EXPECT_EQ(fs::path(name).filename().string().rfind(".tmp", 0), std::string::npos) << name << " left behind";
  }
}

// Pairs are encoded and written on the writer thread while the next renders
// (pair_writer.h): a write that fails there (frame 602's left image cannot
// replace the folder in its place) stops the run with one line naming the
// file and exit code 1; the pair before it is complete, the failed pair has no
// sidecar, and once the obstacle is gone a rerun renders just that pair.
TEST_F(RenderResume, WriterErrorStopsTheRunWithOneLineAndResumes) {
  const fs::path blocker = dataset_ / "frames" / "000602_left.png";
  fs::create_directories(blocker / "in-the-way");
  Inputs three;
  three.extra = "--frames 600:603";
  const test::CommandResult failed = RunCommand(RenderCommand(dataset_, three));
  EXPECT_EQ(failed.exit_code, 1) << failed.output;
  EXPECT_EQ(failed.output.rfind("aar-render: error: " + blocker.string() + ": ", 0), 0u) << failed.output;
  EXPECT_EQ(std::count(failed.output.begin(), failed.output.end(), '\n'), 1) << failed.output;
  EXPECT_TRUE(
      SidecarVerified(dataset_, SidecarPath(dataset_, "frame", 601), ReadManifest(dataset_).frame_settings_sha256));
  EXPECT_FALSE(fs::exists(SidecarPath(dataset_, "frame", 602)));

  fs::remove_all(blocker);
  const test::CommandResult resumed = RunCommand(RenderCommand(dataset_, three));
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  EXPECT_NE(resumed.output.find("1 pairs rendered, 2 already complete"), std::string::npos) << resumed.output;
  EXPECT_TRUE(
      SidecarVerified(dataset_, SidecarPath(dataset_, "frame", 602), ReadManifest(dataset_).frame_settings_sha256));
}

// Both start before either has written its manifest; whichever takes the
// manifest lock first makes the dataset, the other is refused.
TEST(RenderConcurrent, TwoRendersWithDifferentSettingsOneIsAccepted) {
  TempDir dir;
  const fs::path out = dir / "dataset";
  Inputs x1, x4;
  x4.extra = "--msaa 4";
  const std::string both = "(" + RenderCommand(out, x1) + " > " + (dir / "a.log").string() + " 2>&1; echo $? > " +
                           (dir / "a.rc").string() + ") & (" + RenderCommand(out, x4) + " > " +
                           (dir / "b.log").string() + " 2>&1; echo $? > " + (dir / "b.rc").string() + ") & wait";
  ASSERT_EQ(RunCommand(both).exit_code, 0);
  const std::string a = ReadFileBytes(dir / "a.rc"), b = ReadFileBytes(dir / "b.rc");
  const std::string logs = ReadFileBytes(dir / "a.log") + ReadFileBytes(dir / "b.log");
  EXPECT_TRUE((a == "0\n" && b == "1\n") || (a == "1\n" && b == "0\n")) << a << b << logs;
  EXPECT_NE(logs.find("made with other settings (frames.msaa"), std::string::npos) << logs;
}

}  // namespace
}  // namespace aar
