// Refusals that keep a dataset or an output whole, through the executables:
// board images verified by `calibrate`, no output inside a dataset or over
// files the tool did not write, outputs replaced as a whole, options that
// cannot work, and paths the file system refuses. Each refusal is one line
// naming the file and the reason, exit 1, and the folder that holds the
// dataset and the outputs is byte for byte what it was.

#include <gtest/gtest.h>

#include <map>
#include <string>
#include <vector>

#include "aar/dataset.h"
#include "aar/file_io.h"
#include "aar/output_folder.h"
#include "pipeline_support.h"

namespace aar {
namespace {

namespace fs = std::filesystem;
using test::Quote;
using test::RunAnalyze;
using test::SharedDatasets;
using test::TempDir;

// Everything under `root`: files by content hash, folders and links by kind.
std::map<std::string, std::string> Snapshot(const fs::path& root) {
  std::map<std::string, std::string> entries;
  for (auto it = fs::recursive_directory_iterator(root); it != fs::recursive_directory_iterator(); ++it) {
    const std::string name = it->path().lexically_relative(root).string();
    if (it->is_symlink()) {
      entries[name] = "link " + fs::read_symlink(it->path()).string();
      it.disable_recursion_pending();
    } else if (it->is_directory()) {
      entries[name] = "folder";
    } else if (!it->is_regular_file()) {
      entries[name] = "special";
    } else {
      entries[name] = Sha256File(it->path());
    }
  }
  return entries;
}

// A refusal: exit 1, one line "aar-...: error: " with every name in `names`, and nothing changed under `root`.
void ExpectRefused(const test::CommandResult& r, const std::vector<std::string>& names, const fs::path& root,
                   const std::map<std::string, std::string>& before) {
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_EQ(test::CountLines(r.output), 1u) << r.output;
  EXPECT_NE(r.output.find(": error: "), std::string::npos) << r.output;
  for (const std::string& name : names) EXPECT_NE(r.output.find(name), std::string::npos) << name << " in " << r.output;
  EXPECT_EQ(Snapshot(root), before) << "a refused command changed " << root;
}

class Reliability : public ::testing::Test {
 protected:
  void SetUp() override { ASSERT_DATASETS(); }
  // A copy of the near-contact dataset (12 board pairs, 8 frames with depth truth).
  fs::path CopyNearContact() {
    const fs::path dataset = dir_ / "dataset";
    test::CopyDataset(SharedDatasets().near_contact, dataset);
    return dataset;
  }
  TempDir dir_{"reliability"};
};

TEST_F(Reliability, CalibrateVerifiesTheBoardImages) {
  const fs::path dataset = CopyNearContact();
  const fs::path swapped = dataset / "calib" / "000003_left.png";
  fs::copy_file(dataset / "calib" / "000004_left.png", swapped, fs::copy_options::overwrite_existing);
  const auto before = Snapshot(dir_.path());
  ExpectRefused(RunAnalyze("calibrate " + Quote(dataset) + " --out " + Quote(dir_ / "calibration")),
                {swapped.string(), "SHA-256 differs from the sidecar's"}, dir_.path(), before);
  // `run` calibrates from the same boards first.
  ExpectRefused(RunAnalyze("run " + Quote(dataset) + " --no-progress --out " + Quote(dir_ / "run")),
                {swapped.string(), "SHA-256 differs from the sidecar's"}, dir_.path(), before);
}

TEST_F(Reliability, NoOutputInsideADataset) {
  const fs::path dataset = CopyNearContact();
  const fs::path shard = dir_ / "shard";
  fs::create_directories(shard);
  const std::string calibration = " --calibration " + Quote(dataset / kIdealCalibrationName);
  const auto before = Snapshot(dir_.path());
  for (const fs::path& out : {dataset, dataset / "results" / "x", dataset / "frames"}) {
    SCOPED_TRACE(out);
    const std::string where = out == dataset ? "is the dataset " : "is inside the dataset ";
    ExpectRefused(RunAnalyze("run " + Quote(dataset) + " --no-progress" + calibration + " --out " + Quote(out)),
                  {out.string(), where + dataset.string()}, dir_.path(), before);
    ExpectRefused(RunAnalyze("calibrate " + Quote(dataset) + " --out " + Quote(out)), {out.string(), where},
                  dir_.path(), before);
    ExpectRefused(RunAnalyze("export " + Quote(dataset) + " --format ros --out " + Quote(out)), {out.string(), where},
                  dir_.path(), before);
    ExpectRefused(RunAnalyze("merge " + Quote(shard) + " --out " + Quote(out)), {out.string(), where}, dir_.path(),
                  before);
  }
  // `cd DATASET && aar-analyze run .`: the default output folder, results/dataset-shelled, is inside it.
  ExpectRefused(test::RunCommand("cd " + Quote(dataset) + " && " + Quote(test::AnalyzeExe()) + " run . --no-progress" +
                                 calibration),
                {"results/dataset-shelled: is inside the dataset " + dataset.string()}, dir_.path(), before);
}

TEST_F(Reliability, AFolderTheToolDidNotWriteIsNeverReplaced) {
  const fs::path out = dir_ / "mine";
  fs::create_directories(out);
  WriteFileAtomic(out / "notes.txt", "my notes");
  const auto before = Snapshot(dir_.path());
  ExpectRefused(RunAnalyze("export " + Quote(SharedDatasets().near_contact) + " --format ros --out " + Quote(out)),
                {out.string(), "holds files that aar-analyze did not write"}, dir_.path(), before);
  WriteFileAtomic(dir_ / "file", "a file");
  ExpectRefused(RunAnalyze("calibrate " + Quote(SharedDatasets().near_contact) + " --out " + Quote(dir_ / "file")),
                {(dir_ / "file").string(), "exists and is not a folder"}, dir_.path(), Snapshot(dir_.path()));
}

// An export into an earlier export's folder replaces it as a whole: a shorter
// range leaves no stale frames, and an export that fails half way leaves the
// earlier export exactly as it was.
TEST_F(Reliability, ExportsReplaceTheWholeFolderOrNothing) {
  const fs::path dataset = CopyNearContact();
  const fs::path out = dir_ / "bop";
  const auto rgb_count = [&] {
    size_t n = 0;
    for (const auto& entry : fs::recursive_directory_iterator(out)) {
      n += entry.path().parent_path().filename() == "rgb";
    }
    return n;
  };
  ASSERT_EQ(RunAnalyze("export " + Quote(dataset) + " --format bop --out " + Quote(out)).exit_code, 0);
  const size_t all = rgb_count();
  ASSERT_EQ(RunAnalyze("export " + Quote(dataset) + " --format bop --frames 0:3 --out " + Quote(out)).exit_code, 0);
  EXPECT_EQ(rgb_count(), all * 3 / test::kNearContactFrames);
  EXPECT_TRUE(fs::is_regular_file(out / kOutputMarkerName));

  // Frame 5's depth is garbage, its sidecar and the manifest vouch for it: the export fails at frame 5.
  const fs::path depth = dataset / "frames" / "000005_left_depth.exr";
  WriteFileAtomic(depth, "not an EXR");
  const fs::path sidecar_path = SidecarPath(dataset, "frame", 5);
  FrameSidecar sidecar = ReadSidecar(sidecar_path);
  sidecar.files["left_depth"].sha256 = Sha256File(depth);
  WriteJsonFile(sidecar_path, SidecarToJson(sidecar));
  nlohmann::json manifest = ReadJsonFile(dataset / kManifestName);
  manifest["files"]["frames/000005_left_depth.exr"] = Sha256File(depth);
  manifest["files"]["frames/000005.json"] = Sha256File(sidecar_path);
  WriteJsonFile(dataset / kManifestName, manifest);
  const auto before = Snapshot(dir_.path());
  ExpectRefused(RunAnalyze("export " + Quote(dataset) + " --format bop --out " + Quote(out)), {depth.string()},
                dir_.path(), before);
}

TEST_F(Reliability, OptionsThatCannotWorkAreRefused) {
  const fs::path dataset = dir_ / "dataset";
  test::CopyDataset(SharedDatasets().out_of_view, dataset);  // no depth truth, no propellers
  const auto before = Snapshot(dir_.path());
  const std::string run = "run " + Quote(dataset) + " --no-progress --calibration " +
                          Quote(dataset / kIdealCalibrationName) + " --out " + Quote(dir_ / "out") + " ";
  const std::vector<std::pair<std::string, std::vector<std::string>>> cases = {
      {"--truth-cloud", {"--truth-cloud: ", "records no depth truth"}},
      {"--mask-propellers", {"--mask-propellers: ", "records no turning propellers"}},
      {"--num-disparities 1000000", {"num_disparities (--num-disparities) must be a multiple of 16 from 16 to 4096"}},
      {"--num-disparities 1024", {"--num-disparities 1024: must be below the image width (1024 px"}},
      {"--disparity-offset inf", {"--disparity-offset inf: expected a finite offset"}},
      {"--disparity-noise 0", {"--disparity-noise 0.000: ", "disparity noise in (0, 100] px"}},
  };
  for (const auto& [flags, names] : cases) {
    SCOPED_TRACE(flags);
    ExpectRefused(RunAnalyze(run + flags), names, dir_.path(), before);
  }
}

TEST_F(Reliability, PathsTheFileSystemRefusesGetOneLine) {
  const fs::path long_name = dir_ / std::string(300, 'd');
  const fs::path loop = dir_ / "loop";
  fs::create_symlink("loop", loop);
  const auto before = Snapshot(dir_.path());
  const std::string render = Quote(test::RenderExe()) + " ";
  for (const fs::path& dataset : {long_name, loop}) {
    SCOPED_TRACE(dataset);
    const std::string reason = dataset == loop ? "Too many levels of symbolic links" : "File name too long";
    const std::string out = " --out " + Quote(dir_ / "out");
    ExpectRefused(RunAnalyze("run " + Quote(dataset) + " --no-progress" + out), {dataset.string(), reason}, dir_.path(),
                  before);
    ExpectRefused(RunAnalyze("calibrate " + Quote(dataset) + out), {dataset.string(), reason}, dir_.path(), before);
    ExpectRefused(RunAnalyze("export " + Quote(dataset) + " --format ros" + out), {dataset.string(), reason},
                  dir_.path(), before);
    ExpectRefused(test::RunCommand(render + "render " + Quote(dataset) + " --no-progress --frames 0:1"),
                  {dataset.string(), reason}, dir_.path(), before);
    ExpectRefused(test::RunCommand(render + "calib " + Quote(dataset) + " --no-progress --frames 0:1"),
                  {dataset.string(), reason}, dir_.path(), before);
    ExpectRefused(
        RunAnalyze("run " + Quote(SharedDatasets().near_contact) + " --no-progress --receiver " + Quote(dataset) + out),
        {dataset.string(), reason}, dir_.path(), before);
  }
  // A FIFO where a file is read: refused, not waited on.
  ASSERT_EQ(test::RunCommand("mkfifo " + Quote(dir_ / "fifo")).exit_code, 0);
  ExpectRefused(
      test::RunCommand(render + "render " + Quote(dir_ / "new") + " --no-progress --rig " + Quote(dir_ / "fifo")),
      {(dir_ / "fifo").string(), "not a regular file"}, dir_.path(), Snapshot(dir_.path()));
}

}  // namespace
}  // namespace aar
