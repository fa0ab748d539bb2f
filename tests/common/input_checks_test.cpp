// The common layer's input checks: calibration YAML (strict reader, never
// OpenCV's), manifests, rigs, flight-path headers, frame selection and Slurm
// arrays, glTF accessor bounds; and the folder locks with the removal of
// interrupted writes' temporaries.

#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <cstdlib>
#include <nlohmann/json.hpp>
#include <string>

#include "../test_support.h"
#include "aar/calibration_yaml.h"
#include "aar/data_path.h"
#include "aar/dataset.h"
#include "aar/error.h"
#include "aar/file_io.h"
#include "aar/flight_path.h"
#include "aar/folder_lock.h"
#include "aar/frame_selection.h"
#include "aar/gltf_accessor.h"
#include "aar/rig.h"
#include "aar/stereo_calibration.h"
#include "aar/text.h"

namespace aar {
namespace {

using test::SourcePath;
using test::TempDir;

using test::ErrorOf;

bool Contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

StereoCalibration Ideal() { return IdealCalibration(LoadRig(SourcePath("scenes/rig.json"))); }

TEST(CalibrationYaml, ReadsWhatOpenCvWritesExactly) {
  TempDir dir;
  const StereoCalibration ideal = Ideal();
  WriteCalibration(dir / "c.yaml", ideal);
  const StereoCalibration read = ReadCalibration(dir / "c.yaml");
  EXPECT_EQ(read.image_size, ideal.image_size);
  for (const auto& [a, b] : {std::pair{&read.M1, &ideal.M1},
                             {&read.T, &ideal.T},
                             {&read.P2, &ideal.P2},
                             {&read.Q, &ideal.Q},
                             {&read.D2, &ideal.D2}}) {
    ASSERT_EQ(a->size(), b->size());
    EXPECT_EQ(cv::norm(*a, *b, cv::NORM_INF), 0.0);
  }
}

TEST(CalibrationYaml, AcceptsCommentsStringsAndNoDirective) {
  const auto nodes = ParseOpenCvYaml(
      "# another tool\ncalibration_time: \"Tue Dec  1\"\nwidth: 1024\nv: [ 1, -2.5e1,\n  .5 ]\n", "x.yaml");
  ASSERT_TRUE(nodes.contains("v"));
  EXPECT_EQ(nodes.at("v").cols, 3);
  EXPECT_EQ(nodes.at("v").at<double>(0, 1), -25.0);
  EXPECT_EQ(nodes.at("width").at<double>(0, 0), 1024.0);
  EXPECT_FALSE(nodes.contains("calibration_time"));
}

// Each malformed file gives one aar::Error naming the file (and line). The
// ones marked were measured: OpenCV 4.6's FileStorage throws a non-OpenCV
// exception on them (the old reader's "internal error"); none reaches it now.
TEST(CalibrationYaml, MalformedFilesGiveOneNamedError) {
  TempDir dir;
  const std::string good = CalibrationToYaml(Ideal());
  std::string no_dt = good;  // measured: FileStorage throws std::exception
  no_dt.replace(no_dt.find("dt: d"), 5, ":t: d");
  std::string short_data = good;
  short_data.replace(short_data.find("data: [ 0., 0., 0., 0., 0. ]"), 28, "data: [ 0., 0. ]");
  std::string zero_q = good.substr(0, good.find("Q: !!opencv-matrix")) +
                       "Q: !!opencv-matrix\n   rows: 4\n   cols: 4\n   dt: d\n   data: [ 0., 0., 0., 0., 0., 0., 0., "
                       "0., 0., 0., 0., 0., 0., 0., 0., 0. ]\n";
  const std::vector<std::tuple<std::string, std::string, std::string>> cases = {
      {"nul.yaml", std::string("%YAML:1.0\n\0\x01", 13), "holds NUL bytes"},
      {"open.yaml", "%YAML:1.0\n---\nimage_size: [ 1024,\n", ":3: '[' without ']'"},
      {"nested.yaml", "%YAML:1.0\na: [ 1, [ 2 ] ]\n", ":2: malformed sequence"},
      {"mapping.yaml", "{ a: 1 }\n", ":1: expected 'name: value'"},
      {"no-dt.yaml", no_dt, "unexpected or repeated '' inside the matrix"},
      {"short.yaml", short_data, "matrix is 1x5 but data holds 2 values"},
      {"huge-rows.yaml", "M1: !!opencv-matrix\n   rows: 100000\n   cols: 3\n   dt: d\n   data: [ 1 ]\n",
       ":2: rows must be an integer from 1 to 64"},
      {"text.yaml", "M1: !!opencv-matrix\n   rows: 1\n   cols: 1\n   dt: d\n   data: [ one ]\n",
       ":5: 'one' is not a number"},
      {"twice.yaml", "a: 1\na: 2\n", ":2: node 'a' appears twice"},
      {"no-value.yaml", "a:\n  b: 1\n", ":1: node 'a' has no value"},
      {"zero-q.yaml", zero_q, "Q has no focal length"},
      {"no-size.yaml", "%YAML:1.0\nM1: [ 1 ]\n", "missing or bad image_size"},
  };
  for (const auto& [name, text, reason] : cases) {
    SCOPED_TRACE(name);
    WriteFileAtomic(dir / name, text);
    const std::string message = ErrorOf([&] { ReadCalibration(dir / name); });
    EXPECT_TRUE(Contains(message, (dir / name).string())) << message;
    EXPECT_TRUE(Contains(message, reason)) << message;
    EXPECT_FALSE(Contains(message, "\n")) << message;
  }
  // Over the size limit: refused before reading.
  WriteFileAtomic(dir / "big.yaml", std::string(kMaxCalibrationYamlBytes + 1, '#'));
  EXPECT_TRUE(Contains(ErrorOf([&] { ReadCalibration(dir / "big.yaml"); }), "larger than a calibration file"));
}

TEST(Manifest, RefusesEmptyOrWrongFilesAndHugeCounts) {
  TempDir dir;
  const auto manifest_error = [&](const nlohmann::json& j) {
    WriteJsonFile(dir / kManifestName, j);
    return ErrorOf([&] { ReadManifest(dir.path()); });
  };
  nlohmann::json ok = {{"schema", kDatasetSchema},
                       {"frames", {{"count", 2}}},
                       {"complete", false},
                       {"files", {{"rig.json", std::string(64, 'a')}}}};
  EXPECT_EQ(manifest_error(ok), "");
  nlohmann::json j = ok;
  j["files"] = nlohmann::json::array();
  EXPECT_TRUE(Contains(manifest_error(j), "'files' must map relative paths to SHA-256"));
  j = ok;
  j["files"] = nlohmann::json::object();
  j["complete"] = true;
  EXPECT_TRUE(Contains(manifest_error(j), "complete, but 'files' lists nothing"));
  j = ok;
  j["frames"]["count"] = 1000000000000000ull;
  EXPECT_TRUE(Contains(manifest_error(j), "frames.count 1000000000000000 is above 10000000"));
  j = ok;
  j["files"]["rig.json"] = "not-a-hash";
  EXPECT_TRUE(Contains(manifest_error(j), "files['rig.json'] is not a SHA-256"));
}

TEST(Rig, RefusesNonPositiveOrNonFiniteNearPlane) {
  nlohmann::json rig = nlohmann::json::parse(ReadFileBytes(SourcePath("scenes/rig.json")));
  for (const nlohmann::json& near : {nlohmann::json(0.0), nlohmann::json(-1.0), nlohmann::json("0.5")}) {
    rig["near_m"] = near;
    const std::string message = ErrorOf([&] { RigFromJson(rig, "r.json"); });
    EXPECT_TRUE(Contains(message, "r.json: ")) << message;
    EXPECT_TRUE(Contains(message, "near_m")) << message;
  }
}

TEST(Rig, RepeatedKeysAndUnknownDistortionCoefficientsAreRefused) {
  TempDir dir;
  const std::string rig = ReadFileBytes(SourcePath("scenes/rig-distorted.json"));
  const size_t k1 = rig.find("\"k1\": -0.15");
  ASSERT_NE(k1, std::string::npos);
  WriteFileAtomic(dir / "twice.json", std::string(rig).insert(k1, "\"k1\": 0.3, "));
  EXPECT_TRUE(Contains(ErrorOf([&] { LoadRig(dir / "twice.json"); }),
                       (dir / "twice.json").string() + ": key \"k1\" appears twice in one object"));
  WriteFileAtomic(dir / "k4.json", std::string(rig).insert(k1, "\"k4\": 0.3, "));
  EXPECT_TRUE(Contains(ErrorOf([&] { LoadRig(dir / "k4.json"); }),
                       "distortion.k4 is not a Brown-Conrady coefficient (k1, k2, p1, p2, k3)"));
}

TEST(Sensor, ElectronCountsBeyondTheFloatModelAreRefused) {
  nlohmann::json rig = nlohmann::json::parse(ReadFileBytes(SourcePath("scenes/rig-noisy.json")));
  for (const char* field : {"exposure_e", "full_well_e", "read_noise_e", "dsnu_e"}) {
    nlohmann::json changed = rig;
    changed["sensor"][field] = 1e308;
    const std::string message = ErrorOf([&] { RigFromJson(changed, "r.json"); });
    EXPECT_TRUE(Contains(message, std::string("r.json: sensor.") + field)) << message;
    EXPECT_TRUE(Contains(message, "1e9]")) << message;
  }
}

// A message quoting a file stays whole and on one line, and a huge value prints as digits.
TEST(ErrorMessages, ControlBytesAreEscapedAndHugeValuesPrinted) {
  EXPECT_EQ(std::string(Error(std::string("f.csv: field 'a\0b\nc'", 20)).what()), "f.csv: field 'a\\x00b\\x0Ac'");
  EXPECT_EQ(FormatFixed(1e308, 4), "1e+308");
  EXPECT_EQ(FormatFixed(-2.5, 1), "-2.5");
  TempDir dir;
  WriteFileAtomic(dir / "path.csv",
                  "time_s,x_m,y_m,z_m,roll_deg,pitch_deg,yaw_deg,boom_pitch_deg,boom_roll_deg,boom_extension_m\n"
                  "0,-47,0,-19,0,0,0,1e300,0,0\n");
  const std::string message = ErrorOf([&] { ReadFlightPath(dir / "path.csv"); });
  EXPECT_TRUE(Contains(message, "boom_pitch_deg 1e+300 must be in [0.0, 45.0]")) << message;
}

// Found by tests/fuzz (UBSan): nlohmann's get<int>() and get<size_t>() cast a
// float such as 1e300 with undefined behaviour.
TEST(JsonIntegers, FloatsAndOutOfRangeValuesAreRefusedByName) {
  nlohmann::json rig = nlohmann::json::parse(ReadFileBytes(SourcePath("scenes/rig.json")));
  for (const nlohmann::json& width :
       {nlohmann::json(1e300), nlohmann::json(1024.0), nlohmann::json(-3), nlohmann::json(20000)}) {
    rig["image_width"] = width;
    EXPECT_TRUE(Contains(ErrorOf([&] { RigFromJson(rig, "r.json"); }), "r.json: image_width")) << width;
  }
  TempDir dir;
  nlohmann::json sidecar = nlohmann::json::parse(ReadFileBytes(SourcePath("tests/fuzz/corpus/sidecar/frame.json")));
  for (const nlohmann::json& index : {nlohmann::json(1e300), nlohmann::json(-1), nlohmann::json(2.5)}) {
    sidecar["index"] = index;
    WriteJsonFile(dir / "000000.json", sidecar);
    EXPECT_TRUE(Contains(ErrorOf([&] { ReadSidecar(dir / "000000.json"); }), "000000.json: index")) << index;
  }
}

TEST(FlightPath, AcceptsAUtf8ByteOrderMarkAndQuotesBadHeadersVisibly) {
  TempDir dir;
  WriteFileAtomic(dir / "bom.csv", std::string("\xEF\xBB\xBF") + kFlightPathHeader + "\n0,-47,0,-19,0,0,0\n");
  EXPECT_EQ(ReadFlightPath(dir / "bom.csv").size(), 1u);
  WriteFileAtomic(dir / "bad.csv", std::string("\xFE\xFFtime_s,x_m\n0,1\n"));
  const std::string message = ErrorOf([&] { ReadFlightPath(dir / "bad.csv"); });
  EXPECT_TRUE(Contains(message, "bad.csv:1: wrong header '\\xFE\\xFFtime_s,x_m'")) << message;
}

class ScopedEnv {
 public:
  ScopedEnv(const char* name, const char* value) : name_(name) { ::setenv(name, value, 1); }
  ~ScopedEnv() { ::unsetenv(name_); }

 private:
  const char* name_;
};

TEST(FrameSelection, RangePastTheEndAndNonContiguousSlurmArraysAreRefused) {
  const FrameSelection past = ParseFrameSelection("700:800", "");
  EXPECT_TRUE(Contains(ErrorOf([&] { past.CheckWithin(609, "conops.csv"); }),
                       "conops.csv: --frames starts at 700, past the last frame (609 frames, 0 to 608)"));
  EXPECT_EQ(ErrorOf([] { ParseFrameSelection("600:800", "").CheckWithin(609, "x"); }), "");
  EXPECT_EQ(ParseFrameSelection("", "1/4").ShardSuffix(), "-shard1of4");
  EXPECT_EQ(ParseFrameSelection("", "").ShardSuffix(), "");
  {
    // --array=0-6:2 (tasks 0, 2, 4, 6): shards ID - MIN would overlap and miss frames.
    ScopedEnv id("SLURM_ARRAY_TASK_ID", "2"), count("SLURM_ARRAY_TASK_COUNT", "4"), min("SLURM_ARRAY_TASK_MIN", "0"),
        max("SLURM_ARRAY_TASK_MAX", "6"), step("SLURM_ARRAY_TASK_STEP", "2");
    EXPECT_TRUE(Contains(ErrorOf([] { ParseFrameSelection("", ""); }), "Slurm array is not contiguous"));
  }
  {
    ScopedEnv id("SLURM_ARRAY_TASK_ID", "5"), count("SLURM_ARRAY_TASK_COUNT", "4"), min("SLURM_ARRAY_TASK_MIN", "3"),
        max("SLURM_ARRAY_TASK_MAX", "6");
    const FrameSelection s = ParseFrameSelection("", "");
    EXPECT_EQ(s.shard_index, 2u);
    EXPECT_EQ(s.shard_count, 4u);
  }
}

// A POSITION accessor whose count makes (count - 1) * stride + 12 wrap to 12
// bytes: the bounds check must see through the wraparound.
TEST(GltfAccessor, HugeCountDoesNotWrapTheBoundsCheck) {
  tinygltf::Model model;
  model.buffers.resize(1);
  model.buffers[0].data.resize(12);
  model.bufferViews.resize(1);
  model.bufferViews[0].buffer = 0;
  model.bufferViews[0].byteLength = 12;
  model.accessors.resize(1);
  tinygltf::Accessor& a = model.accessors[0];
  a.bufferView = 0;
  a.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
  a.type = TINYGLTF_TYPE_VEC3;
  a.count = (size_t{1} << 62) + 1;  // (2^62) * 12 = 3 * 2^64: wraps to 0
  EXPECT_TRUE(Contains(ErrorOf([&] { GltfAccessor(model, 0, "m.gltf"); }), "m.gltf: accessor 0 reads past the end"));
  a.count = 1;
  a.byteOffset = static_cast<size_t>(-8);  // byteOffset + 12 wraps
  EXPECT_TRUE(Contains(ErrorOf([&] { GltfAccessor(model, 0, "m.gltf"); }), "reads past the end"));
  a.byteOffset = 0;
  EXPECT_EQ(GltfAccessor(model, 0, "m.gltf").count(), 1u);
}

TEST(FolderLock, ExclusiveConflictsSharedDoesNot) {
  TempDir dir;
  const std::filesystem::path file = dir / "x.lock";
  {
    FileLock shared_a(file, LockMode::kShared);
    EXPECT_TRUE(FileLock::TryLock(file, LockMode::kShared).held());
    EXPECT_FALSE(FileLock::TryLock(file, LockMode::kExclusive).held());
  }
  FileLock exclusive = FileLock::TryLock(file, LockMode::kExclusive);
  ASSERT_TRUE(exclusive.held());
  EXPECT_FALSE(FileLock::TryLock(file, LockMode::kShared).held());
  exclusive.Change(LockMode::kShared);
  EXPECT_TRUE(FileLock::TryLock(file, LockMode::kShared).held());

  const FileLock out = LockOutputFolder(dir.path());
  EXPECT_TRUE(Contains(ErrorOf([&] { LockOutputFolder(dir.path()); }), "output folder in use by another run"));
}

TEST(FolderLock, RemovesOnlyTemporaries) {
  TempDir dir;
  WriteFileAtomic(dir / "keep.json", "{}");
  WriteFileAtomic(dir / ".tmp123.000000_left.png", "partial");
  WriteFileAtomic(dir / ".tmp9.manifest.json", "partial");
  EXPECT_EQ(RemoveStaleTemporaries(dir.path()), 2u);
  EXPECT_TRUE(std::filesystem::exists(dir / "keep.json"));
  EXPECT_FALSE(std::filesystem::exists(dir / ".tmp123.000000_left.png"));
}

TEST(DataPath, BuildTreeToolsFindTheSourceTree) {
  EXPECT_TRUE(std::filesystem::is_regular_file(DataFile("scenes/rig.json")));
  EXPECT_TRUE(std::filesystem::is_regular_file(DataFile("flightpaths/conops.csv")));
}

}  // namespace
}  // namespace aar
