// OpenedDataset: a dataset folder opened once, every file checked against
// the SHA-256 the manifest (and a sidecar) records, on a small hand-made
// dataset of one frame.

#include "aar/opened_dataset.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>

#include "../test_support.h"
#include "aar/dataset.h"
#include "aar/file_io.h"
#include "aar/json_file.h"
#include "aar/stereo_calibration.h"

namespace aar {
namespace {

using test::ErrorOf;
using test::SourcePath;
using test::TempDir;

bool Contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// One frame: rig, flight path, sidecar, two "images" and the ideal calibration, all hashed in the manifest.
class OpenedDatasetTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const std::string rig = ReadFileBytes(SourcePath("scenes/rig.json"));
    Write(kRigName, rig);
    Write(kFlightPathName, std::string(kFlightPathHeader) + "\n0.5,30,0,5,0,0,0\n");
    Write("frames/000000_left.png", "left bytes");
    Write("frames/000000_right.png", "right bytes");
    Write(kIdealCalibrationName, CalibrationToYaml(IdealCalibration(LoadRig(dir_ / kRigName))));
    FrameSidecar sidecar;
    sidecar.time_s = 0.5;
    sidecar.tanker_from_target.translation_m = {30.0, 0.0, 5.0};
    sidecar.region = "C";
    sidecar.rig = LoadRig(dir_ / kRigName);
    sidecar.files["left"] = {"frames/000000_left.png", Sha256Hex("left bytes")};
    sidecar.files["right"] = {"frames/000000_right.png", Sha256Hex("right bytes")};
    Write("frames/000000.json", SidecarToJson(sidecar).dump(2));
    manifest_ = {{"schema", kDatasetSchema},
                 {"frames", {{"count", 1}}},
                 {"complete", true},
                 {"inputs", {{"rig", {{"file", kRigName}, {"sha256", Sha256Hex(rig)}}}}},
                 {"files", nlohmann::json::object()}};
    for (const char* name : {kRigName, kFlightPathName, kIdealCalibrationName, "frames/000000.json",
                             "frames/000000_left.png", "frames/000000_right.png"}) {
      manifest_["files"][name] = Sha256File(dir_ / name);
    }
    WriteManifest();
  }
  void Write(const std::string& relative, const std::string& bytes) const {
    EnsureWritableDirectory((dir_ / relative).parent_path());
    WriteFileAtomic(dir_ / relative, bytes);
  }
  void WriteManifest() const { WriteJsonFile(dir_ / kManifestName, manifest_); }
  std::string OpenError() const {
    return ErrorOf([&] { OpenedDataset::Open(dir_.path()); });
  }

  TempDir dir_{"opened-dataset"};
  nlohmann::json manifest_;
};

TEST_F(OpenedDatasetTest, ReadsWhatTheManifestRecords) {
  const OpenedDataset dataset = OpenedDataset::Open(dir_.path());
  EXPECT_EQ(dataset.manifest().frame_count, 1u);
  EXPECT_EQ(dataset.manifest_sha256(), Sha256File(dir_ / kManifestName));
  EXPECT_EQ(dataset.rig().left.intrinsics.width_px, LoadRig(SourcePath("scenes/rig.json")).left.intrinsics.width_px);
  ASSERT_EQ(dataset.flight_path().size(), 1u);
  EXPECT_EQ(dataset.flight_path()[0].time_s, 0.5);
  EXPECT_EQ(dataset.Input(kReceiverModelName), nullptr);  // an analysis may bring its own
  const FrameSidecar sidecar = dataset.Sidecar("frame", 0);
  EXPECT_EQ(sidecar.region, "C");
  EXPECT_EQ(dataset.ReadFile(sidecar.files.at("right")), "right bytes");
  ASSERT_TRUE(dataset.ReadIfPresent(kIdealCalibrationName).has_value());
  EXPECT_FALSE(dataset.ReadIfPresent("frames/absent.png").has_value());
}

TEST_F(OpenedDatasetTest, RefusesChangedOrMissingInputs) {
  Write(kRigName, ReadFileBytes(SourcePath("scenes/rig.json")) + " ");
  std::string message = OpenError();
  EXPECT_TRUE(Contains(message, (dir_ / kRigName).string() + ": SHA-256 differs from manifest.json's")) << message;
  // Listed in inputs alone: still checked.
  manifest_["files"].erase(kRigName);
  WriteManifest();
  message = OpenError();
  EXPECT_TRUE(Contains(message, "SHA-256 differs from manifest.json's")) << message;
  Write(kRigName, ReadFileBytes(SourcePath("scenes/rig.json")));
  EXPECT_EQ(OpenError(), "");
  // Inputs recorded in shapes the manifest does not use are not hashes.
  manifest_["inputs"]["flight_path"] = {{"file", 5}, {"sha256", "x"}};
  manifest_["inputs"]["receiver_model"] = "receiver.glb";
  WriteManifest();
  EXPECT_EQ(OpenError(), "");
  manifest_["inputs"]["rig"]["sha256"] = 7;
  WriteManifest();
  EXPECT_TRUE(Contains(OpenError(), "inputs.rig.sha256 is not a string"));
  manifest_["inputs"]["rig"]["sha256"] = Sha256File(dir_ / kRigName);
  // A recorded boom model that is not there.
  manifest_["files"][kBoomModelName] = std::string(64, 'a');
  WriteManifest();
  message = OpenError();
  EXPECT_TRUE(Contains(message, (dir_ / kBoomModelName).string() + ": missing (manifest.json records it)")) << message;
}

TEST_F(OpenedDatasetTest, RefusesManifestsThatDisagreeWithTheFolder) {
  manifest_["frames"]["count"] = 2;
  WriteManifest();
  std::string message = OpenError();
  EXPECT_TRUE(Contains(message, "frames.count 2 differs from the 1 samples of")) << message;
  manifest_["frames"]["count"] = 1;
  manifest_["files"].erase("frames/000000.json");
  WriteManifest();
  const OpenedDataset dataset = OpenedDataset::Open(dir_.path());
  message = ErrorOf([&] { dataset.Sidecar("frame", 0); });
  EXPECT_TRUE(Contains(message, "complete, but 'files' does not list frames/000000.json")) << message;
  std::filesystem::remove(dir_ / kManifestName);
  EXPECT_TRUE(Contains(OpenError(), "no manifest"));
}

TEST_F(OpenedDatasetTest, ChecksSidecarsAndTheirFilesAsTheyAreRead) {
  const OpenedDataset dataset = OpenedDataset::Open(dir_.path());
  const FrameSidecar sidecar = dataset.Sidecar("frame", 0);
  Write("frames/000000_left.png", "other bytes");
  std::string message = ErrorOf([&] { dataset.ReadFile(sidecar.files.at("left")); });
  EXPECT_TRUE(Contains(message, "000000_left.png: SHA-256 differs from the sidecar's")) << message;
  Write("frames/000000.json", ReadFileBytes(dir_ / "frames/000000.json") + "\n");
  message = ErrorOf([&] { dataset.Sidecar("frame", 0); });
  EXPECT_TRUE(Contains(message, "000000.json: SHA-256 differs from manifest.json's")) << message;
  message = ErrorOf([&] { dataset.Sidecar("frame", 1); });
  EXPECT_TRUE(Contains(message, "000001.json: sidecar missing (not rendered)")) << message;
  Write(kIdealCalibrationName, "%YAML:1.0\n");
  message = ErrorOf([&] { dataset.ReadIfPresent(kIdealCalibrationName); });
  EXPECT_TRUE(Contains(message, "calibration_ideal.yaml: SHA-256 differs from manifest.json's")) << message;
}

}  // namespace
}  // namespace aar
