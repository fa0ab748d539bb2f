// Bad input to aar-render: one clear message naming the file (and line), a
// non-zero exit, and nothing written; and its command line (help, usage errors).

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "../test_support.h"
#include "aar/file_io.h"

namespace aar {
namespace {

using test::RunCommand;
using test::SourcePath;
using test::TempDir;

struct BadInputCase {
  std::string name;
  std::string csv;            ///< flight-path content ("" = the committed conops.csv)
  std::string extra_flags;    ///< appended to the command line
  std::string env;            ///< prefix, e.g. VK_ICD_FILENAMES=...
  std::string expected_text;  ///< must appear in the message
};

class RenderBadInput : public ::testing::TestWithParam<BadInputCase> {};

// A triangle whose POSITION accessor (3 x VEC3 float, 36 bytes) needs more
// than its 12-byte buffer view holds.
const char* const kBadAccessorGltf =
    R"({"asset":{"version":"2.0"},"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],)"
    R"("meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],)"
    R"("buffers":[{"byteLength":12,"uri":"data:application/octet-stream;base64,AAAAAAAAAAAAAAAA"}],)"
    R"("bufferViews":[{"buffer":0,"byteLength":12}],)"
    R"("accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[0,0,0]}]})";

// The same triangle with count 2^62 + 1: (count - 1) * 12 + 12 wraps around to
// 12 bytes in 64-bit arithmetic, which a naive bounds check lets through.
const char* const kHugeCountGltf =
    R"({"asset":{"version":"2.0"},"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],)"
    R"("meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],)"
    R"("buffers":[{"byteLength":12,"uri":"data:application/octet-stream;base64,AAAAAAAAAAAAAAAA"}],)"
    R"("bufferViews":[{"buffer":0,"byteLength":12}],)"
    R"("accessors":[{"bufferView":0,"componentType":5126,"count":4611686018427387905,"type":"VEC3"}]})";

TEST_P(RenderBadInput, FailsWithOneClearMessageAndWritesNothing) {
  const BadInputCase& c = GetParam();
  TempDir dir("bad-" + c.name);
  std::string csv_path = SourcePath("flightpaths/conops.csv").string();
  if (!c.csv.empty()) {
    csv_path = (dir / "path.csv").string();
    WriteFileAtomic(csv_path, c.csv);
  }
  WriteFileAtomic(dir / "corrupt.glb", "glTF this is not a binary glTF file");
  WriteFileAtomic(dir / "bad-accessor.gltf", kBadAccessorGltf);
  WriteFileAtomic(dir / "huge-count.gltf", kHugeCountGltf);
  std::string rig = ReadFileBytes(SourcePath("scenes/rig.json"));
  rig.replace(rig.find("\"near_m\": 0.5"), 13, "\"near_m\": 0.0");
  WriteFileAtomic(dir / "near0.json", rig);
  // A lens whose radial mapping folds back inside the image, and a distortion in a schema-1 rig.
  std::string lens = ReadFileBytes(SourcePath("scenes/rig-distorted.json"));
  std::string fold = lens;
  fold.replace(fold.find("\"k1\": -0.15"), 11, "\"k1\": -0.6");
  WriteFileAtomic(dir / "fold.json", fold);
  lens.replace(lens.find("aar-rig/2"), 9, "aar-rig/1");
  WriteFileAtomic(dir / "v1-lens.json", lens);
  WriteFileAtomic(dir / "a-file", "x");
  std::string flags = c.extra_flags;
  for (const auto& [key, value] : {std::pair<std::string, std::string>{"@DIR@", dir.path().string()}}) {
    for (size_t at = flags.find(key); at != std::string::npos; at = flags.find(key))
      flags.replace(at, key.size(), value);
  }
  const std::filesystem::path out = dir / "out";
  const std::string command = c.env + " " + test::BinaryPath("renderer/aar-render").string() + " render " +
                              out.string() + " --no-progress --frames 0:1 --msaa 1" + " --rig " +
                              SourcePath("scenes/rig.json").string() + " --receiver " +
                              SourcePath("scenes/c12.glb").string() + " --tanker " +
                              SourcePath("scenes/kc46.glb").string() + " --flight-path " + csv_path + " " + flags;
  const test::CommandResult result = RunCommand(command);
  EXPECT_NE(result.exit_code, 0) << result.output;
  EXPECT_NE(result.output.find(c.expected_text), std::string::npos) << result.output;
  EXPECT_EQ(std::count(result.output.begin(), result.output.end(), '\n'), 1) << result.output;
  EXPECT_FALSE(std::filesystem::exists(out)) << "output was written";
}

const std::string kHeader = "time_s,x_m,y_m,z_m,roll_deg,pitch_deg,yaw_deg\n";

INSTANTIATE_TEST_SUITE_P(
    Cases, RenderBadInput,
    ::testing::Values(
        BadInputCase{"missing-gltf", "", "--receiver @DIR@/missing.glb", "", "missing.glb: model file not found"},
        BadInputCase{"corrupt-gltf", "", "--receiver @DIR@/corrupt.glb", "", "corrupt.glb: not a valid glTF"},
        BadInputCase{"bad-accessor", "", "--receiver @DIR@/bad-accessor.gltf", "",
                     "bad-accessor.gltf: accessor 0 reads past the end of its buffer"},
        BadInputCase{"huge-count", "", "--receiver @DIR@/huge-count.gltf", "",
                     "huge-count.gltf: accessor 0 reads past the end of its buffer"},
        BadInputCase{"near-zero", "", "--rig @DIR@/near0.json", "", "near0.json: near_m must be positive"},
        BadInputCase{"lens-folds", "", "--rig @DIR@/fold.json", "",
                     "fold.json: camera left: lens distortion (k1 -0.6, k2 0.05, p1 0.0001, p2 -0.0001, k3 0) is not "
                     "one-to-one inside the image"},
        BadInputCase{"lens-in-schema-1", "", "--rig @DIR@/v1-lens.json", "",
                     "v1-lens.json: camera left: 'distortion' needs schema \"aar-rig/2\""},
        BadInputCase{"anisotropy-0", "", "--anisotropy 0", "", "--anisotropy 0.000000: expected 1 (trilinear) to 16"},
        BadInputCase{"anisotropy-17", "", "--anisotropy 17", "", "--anisotropy 17.000000: expected 1"},
        BadInputCase{"anisotropy-neg", "", "--anisotropy -1", "", "--anisotropy -1.000000: expected 1"},
        BadInputCase{"anisotropy-nan", "", "--anisotropy nan", "", "--anisotropy nan: expected 1"},
        BadInputCase{"frames-past-end", "", "--frames 700:800", "", "--frames starts at 700, past the last frame"},
        BadInputCase{"sun-half", "", "--sun-azimuth 90", "", "--sun-azimuth and --sun-elevation: give both"},
        BadInputCase{"sun-high", "", "--sun-azimuth 0 --sun-elevation 95", "", "--sun-elevation"},
        BadInputCase{"sun-both-ways", "", "--sun-azimuth 0 --sun-elevation 45 --sun-time 2026-12-06T15:00Z", "",
                     "give one way"},
        BadInputCase{"sun-night", "", "--sun-time 2026-12-06T06:00Z --latitude 35 --longitude -100 --heading 0", "",
                     "below the horizon there"},
        BadInputCase{"sun-bad-time", "", "--sun-time 2026-13-01T00:00Z --latitude 35 --longitude -100 --heading 0", "",
                     "--sun-time '2026-13-01T00:00Z': not a date and time"},
        BadInputCase{"sun-no-place", "", "--sun-time 2026-12-06T15:00Z --latitude 35", "", "give all four"},
        BadInputCase{"daylight-flat", "", "--daylight", "", "--daylight: the flat sky is the thesis's fixed light"},
        BadInputCase{"turbidity-alone", "", "--background sky --turbidity 4", "", "--turbidity: only with --daylight"},
        BadInputCase{"turbidity-high", "", "--background sky --daylight --turbidity 11", "",
                     "--turbidity 11.000000: expected 2.000000 to 10.000000"},
        BadInputCase{"night-flat", "", "--night --exposure-ev 12", "",
                     "--night: the flat sky is the thesis's fixed light"},
        BadInputCase{"night-and-daylight", "", "--background sky --night --daylight", "",
                     "--daylight and --night: give one of them"},
        BadInputCase{"moonlight-alone", "", "--background sky --moonlight 0.1", "", "--moonlight: only with --night"},
        BadInputCase{"moonlight-high", "", "--background sky --night --moonlight 2", "",
                     "--moonlight 2.000000: expected 0.000000 to 1.000000 lx"},
        BadInputCase{"night-dated", "",
                     "--background sky --night --sun-time 2026-12-06T18:00Z --latitude 35 --longitude -100 --heading 0",
                     "", "--night and --sun-time: the time gives the sun's place"},
        BadInputCase{"exposure-high", "", "--exposure-ev 30", "", "--exposure-ev 30.000: expected -10 to 24"},
        BadInputCase{"floodlight-dim", "", "--floodlight 0", "", "--floodlight 0.000: expected 0.1 to 10000 lx"},
        BadInputCase{"beam-alone", "", "--floodlight-beam 5", "", "--floodlight-beam: only with --floodlight"},
        BadInputCase{"beam-wide", "", "--floodlight 50 --floodlight-beam 90", "",
                     "--floodlight-beam 90.000: expected 1 to 60 deg"},
        BadInputCase{"ae-target-alone", "", "--ae-target 0.3", "",
                     "--ae-target, --ae-time-constant and --ae-max-ev: only with --auto-exposure"},
        BadInputCase{"ae-target-high", "", "--auto-exposure --ae-target 2", "",
                     "--ae-target 2.000000: expected a level"},
        BadInputCase{"ae-lag-negative", "", "--auto-exposure --ae-time-constant -1", "",
                     "--ae-time-constant -1.000000: expected 0 (no lag) to 60 [s]"},
        BadInputCase{"wrong-header", "t,x,y,z,r,p,yaw\n0,1,2,3,0,0,0\n", "", "", "path.csv:1: wrong header"},
        BadInputCase{"nan", kHeader + "0,-47,0,-19,0,0,0\n0.5,nan,0,-19,0,0,0\n", "", "",
                     "path.csv:3: field x_m: 'nan' is not a finite number"},
        BadInputCase{"text", kHeader + "0,-47,0,-19,zero,0,0\n", "", "",
                     "path.csv:2: field roll_deg: 'zero' is not a finite number"},
        BadInputCase{"columns", kHeader + "0,-47,0,-19,0,0\n", "", "", "path.csv:2: expected 7 fields, found 6"},
        BadInputCase{"msaa", "", "--msaa 6", "", "unknown MSAA level"},
        BadInputCase{"background-name", "", "--background forest", "", "--background 'forest': expected flat, sky"},
        BadInputCase{"altitude-low", "", "--background terrain --altitude 50", "", "--altitude 50.000000: expected"},
        BadInputCase{"altitude-nan", "", "--background sky --altitude nan", "", "--altitude nan: expected"},
        BadInputCase{"cloud-above-tanker", "", "--background clouds --altitude 5000 --cloud-top 6000", "",
                     "--cloud-top 6000.000000: expected 0.000000 to 4900.000000 m"},
        BadInputCase{"attitude-flat", "", "--tanker-roll 10", "", "the flat sky has no horizon"},
        BadInputCase{"visibility", "", "--background terrain --visibility 10", "", "--visibility 10.000000"},
        BadInputCase{"no-vulkan", "", "", "VK_ICD_FILENAMES=/nonexistent/icd.json", "no Vulkan device"}),
    [](const ::testing::TestParamInfo<BadInputCase>& info) {
      std::string name = info.param.name;
      std::replace(name.begin(), name.end(), '-', '_');
      return name;
    });

// An output folder below a regular file cannot be created.
TEST(RenderBadOutput, UnwritableOutputFolderFailsCleanly) {
  TempDir dir("bad-output");
  WriteFileAtomic(dir / "a-file", "x");
  const std::string command =
      test::BinaryPath("renderer/aar-render").string() + " render " + (dir / "a-file/out").string() +
      " --no-progress --frames 0:1 --msaa 1 --rig " + SourcePath("scenes/rig.json").string() + " --receiver " +
      SourcePath("scenes/c12.glb").string() + " --tanker " + SourcePath("scenes/kc46.glb").string() +
      " --flight-path " + SourcePath("flightpaths/conops.csv").string();
  const test::CommandResult result = RunCommand(command);
  EXPECT_NE(result.exit_code, 0);
  EXPECT_NE(result.output.find("a-file/out: cannot create output folder"), std::string::npos) << result.output;
  EXPECT_EQ(std::count(result.output.begin(), result.output.end(), '\n'), 1) << result.output;
}

// --far-boards takes distances or "none"; anything else fails before a file is written.
TEST(RenderBadOutput, FarBoardsMustBeDistancesOrNone) {
  TempDir dir("bad-far-boards");
  const std::filesystem::path out = dir / "out";
  const std::string command = test::BinaryPath("renderer/aar-render").string() + " calib " + out.string() +
                              " --no-progress --msaa 1 --far-boards 30,far --rig " +
                              SourcePath("scenes/rig.json").string();
  const test::CommandResult result = RunCommand(command);
  EXPECT_NE(result.exit_code, 0);
  EXPECT_NE(result.output.find("--far-boards: 'far' is not a finite number"), std::string::npos) << result.output;
  EXPECT_EQ(std::count(result.output.begin(), result.output.end(), '\n'), 1) << result.output;
  EXPECT_FALSE(std::filesystem::exists(out)) << "output was written";
}

// A rig the ideal calibration cannot describe (here the right camera's focal
// length differs): `calib` and `render` name the rig file; `bench` refuses an
// MSAA level it cannot render before it times anything.
TEST(RenderBadOutput, ImpossibleRigAndBenchLevelAreRefusedByName) {
  TempDir dir("bad-rig-level");
  nlohmann::json rig = nlohmann::json::parse(ReadFileBytes(SourcePath("scenes/rig.json")));
  rig["cameras"]["right"]["fx_px"] = 901.0;
  WriteFileAtomic(dir / "uneven.json", rig.dump(2));
  const std::string exe = test::BinaryPath("renderer/aar-render").string();
  for (const char* command : {"calib", "render"}) {
    const test::CommandResult result = RunCommand(exe + " " + command + " " + (dir / "out").string() +
                                                  " --no-progress --msaa 1 --rig " + (dir / "uneven.json").string());
    EXPECT_EQ(result.exit_code, 1) << result.output;
    EXPECT_EQ(
        result.output.rfind(
            "aar-render: error: " + (dir / "uneven.json").string() + ": ideal calibration needs parallel cameras", 0),
        0u)
        << result.output;
    EXPECT_EQ(std::count(result.output.begin(), result.output.end(), '\n'), 1) << result.output;
    EXPECT_FALSE(std::filesystem::exists(dir / "out")) << "output was written";
  }
  const test::CommandResult bench = RunCommand(exe + " bench --msaa 2 --pairs 1");
  EXPECT_EQ(bench.exit_code, 1) << bench.output;
  EXPECT_EQ(bench.output, "aar-render: error: --msaa 2: unknown MSAA level (use 1, 4, 8, 16 or 32)\n");
}

// The command table: the top-level help lists every subcommand with its
// one-line description, a subcommand's help lists its flags, and a missing or
// unknown subcommand is a usage error.
TEST(RenderCommandLine, HelpListsSubcommandsAndTheirFlags) {
  const std::string render = test::BinaryPath("renderer/aar-render").string();
  const test::CommandResult top = RunCommand(render + " --help");
  EXPECT_EQ(top.exit_code, 0) << top.output;
  for (const char* line :
       {"render                      render a flight path", "calib                       render the calibration board",
        "finalize                    recompute manifest.json", "devices                     list the Vulkan devices",
        "bench                       time stereo pairs per second"}) {
    EXPECT_NE(top.output.find(line), std::string::npos) << line << "\n" << top.output;
  }
  const test::CommandResult sub = RunCommand(render + " render --help");
  EXPECT_EQ(sub.exit_code, 0) << sub.output;
  EXPECT_NE(sub.output.find("Usage: " + render + " render [OPTIONS] output"), std::string::npos) << sub.output;
  for (const char* flag : {"--rig", "--flight-path", "--receiver", "--tanker", "--depth", "--msaa", "--anisotropy",
                           "--frames", "--shard", "--device", "--no-progress", "--background", "--altitude",
                           "--cloud-top", "--tanker-roll", "--tanker-pitch", "--visibility", "--background-seed"}) {
    EXPECT_NE(sub.output.find(flag), std::string::npos) << flag << "\n" << sub.output;
  }
  const test::CommandResult bench = RunCommand(render + " bench --help");
  EXPECT_NE(bench.output.find("--levels"), std::string::npos) << bench.output;
  EXPECT_EQ(bench.output.find("--board"), std::string::npos) << bench.output;
}

TEST(RenderCommandLine, VersionNamesTheReleaseAndTheBuild) {
  const test::CommandResult result = RunCommand(test::BinaryPath("renderer/aar-render").string() + " --version");
  EXPECT_EQ(result.exit_code, 0) << result.output;
  EXPECT_EQ(result.output.rfind(std::string("aar-render ") + AAR_TEST_VERSION + " (git ", 0), 0u) << result.output;
}

TEST(RenderCommandLine, MissingOrUnknownSubcommandIsAUsageError) {
  const std::string render = test::BinaryPath("renderer/aar-render").string();
  for (const std::string args : {"", " bogus"}) {
    const test::CommandResult result = RunCommand(render + args);
    EXPECT_NE(result.exit_code, 0) << args;
    EXPECT_NE(result.output.find("A subcommand is required"), std::string::npos) << result.output;
  }
}

}  // namespace
}  // namespace aar
