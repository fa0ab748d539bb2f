// aar-analyze: offline analysis of AAR stereo datasets (thesis sections
// 3.3-3.7). A table of subcommands, each parsing its flags, validating and
// calling aar_analyzer, where the work lives.

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "aar/analyzer/analysis_run.h"
#include "aar/analyzer/bench_yardstick.h"
#include "aar/analyzer/dataset_export.h"
#include "aar/analyzer/mesh.h"
#include "aar/analyzer/ply.h"
#include "aar/data_path.h"
#include "aar/error.h"
#include "aar/file_io.h"
#include "aar/output_folder.h"
#include "run_flags.h"

namespace {

using aar::cli::DatasetName;
using aar::cli::ReferenceFlags;
using aar::cli::RunFlags;

double Median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

void PrintStageMedians(const std::vector<aar::FrameResult>& frames, const std::optional<double>& yardstick_ms) {
  std::vector<double> load, rectify, disparity, reproject, icp, total, compute;
  for (const aar::FrameResult& f : frames) {
    if (!f.ok()) continue;
    load.push_back(f.times.load_ms);
    rectify.push_back(f.times.rectify_ms);
    disparity.push_back(f.times.disparity_ms);
    reproject.push_back(f.times.reproject_ms);
    icp.push_back(f.times.icp_ms);
    total.push_back(f.times.total_ms);
    compute.push_back(f.times.total_ms - f.times.load_ms);
  }
  std::printf(
      "| frames | load ms | rectify ms | disparity ms | reproject ms | ICP ms | total ms | total - load ms |\n");
  std::printf("|---|---|---|---|---|---|---|---|\n");
  std::printf("| %zu | %.1f | %.1f | %.1f | %.1f | %.1f | %.1f | %.1f |\n", total.size(), Median(load), Median(rectify),
              Median(disparity), Median(reproject), Median(icp), Median(total), Median(compute));
  if (!yardstick_ms) return;
  // The speed targets are in the reference yardstick's milliseconds (docs/performance.md).
  const double scale = aar::kReferenceYardstickMs / *yardstick_ms;
  std::printf(
      "\nyardstick: OpenCV StereoBM (48 disparities, block 9, speckle filter) on the whole rectified pair %.1f ms;\n"
      "in reference ms (x %.1f / %.1f): decoded to pose %.1f, with decode %.1f, ICP %.1f\n",
      *yardstick_ms, aar::kReferenceYardstickMs, *yardstick_ms, scale * Median(compute), scale * Median(total),
      scale * Median(icp));
}

// Parses `app` from argv (argv[0] = the subcommand); returns the exit code
// CLI11 asks for (help, bad flags), or nullopt to go on.
std::optional<int> Parse(CLI::App& app, int argc, char** argv) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  return std::nullopt;
}

int RunCalibrate(int argc, char** argv) {
  CLI::App app{"stereo calibration from DATASET/calib (thesis 3.3)", "aar-analyze calibrate"};
  std::filesystem::path dataset, out;
  aar::CalibrationOptions options;
  app.add_option("dataset", dataset, "dataset folder")->required();
  app.add_option("--out", out, "output folder (default: results/<dataset>-calibration)");
  std::string distortion = aar::DistortionModelName(options.distortion);
  app.add_option("--distortion", distortion,
                 "lens model: auto (brown-conrady when the dataset's rig.json gives its cameras distortion, else "
                 "pinhole), pinhole (k1..k3, p1, p2 fixed at 0), brown-conrady (estimate k1 k2 p1 p2, k3 fixed at "
                 "0) or brown-conrady-k3 (estimate all five)")
      ->capture_default_str();
  app.add_flag(
      "--estimate-distortion", [&](int64_t) { distortion = "brown-conrady-k3"; },
      "the same as --distortion brown-conrady-k3 (all five coefficients, OpenCV's default)");
  app.add_flag("--same-focal-length", options.same_focal_length,
               "one focal length for both cameras (a matched pair; OpenCV's CALIB_SAME_FOCAL_LENGTH)");
  if (const auto code = Parse(app, argc, argv)) return *code;
  options.distortion = aar::ParseDistortionModel(distortion);
  if (out.empty()) out = std::filesystem::path("results") / (DatasetName(dataset) + "-calibration");
  aar::CheckOutputFolder(out);
  const aar::CalibrateOutput result = aar::CalibrateDataset(aar::OpenedDataset::Open(dataset), options);
  aar::StagedOutput staged(out, "calibrate");
  aar::WriteCalibrationOutputs(staged.path(), result);
  staged.Commit();
  std::printf("%s\nwrote %s and %s\n", result.result.BriefReport().c_str(), (out / aar::kCalibrationYamlName).c_str(),
              (out / aar::kCalibrationReportName).c_str());
  return 0;
}

int RunReference(int argc, char** argv) {
  CLI::App app{"build a reference point cloud and write it as PLY", "aar-analyze reference"};
  std::string model = "shelled", receiver = aar::DataFile("scenes/c12.glb"),
              rig_path = aar::DataFile("scenes/rig.json"), out;
  ReferenceFlags reference;
  app.add_option("--model", model, "full or shelled")->capture_default_str();
  app.add_option("--receiver", receiver, "receiver glTF")->capture_default_str();
  app.add_option("--rig", rig_path, "camera rig (shelling uses its contact position)")->capture_default_str();
  reference.Add(&app);
  app.add_option("--out", out, "PLY file (default: reference_<model>.ply)");
  if (const auto code = Parse(app, argc, argv)) return *code;
  const aar::TriangleMesh mesh = aar::LoadReceiverMesh(receiver);
  const aar::StereoRig rig = aar::LoadRig(rig_path);
  const aar::ReferenceModel result = aar::BuildReferenceModel(mesh, rig, {model, reference.Resolve()});
  if (out.empty()) out = "reference_" + result.name + ".ply";
  aar::WritePly(out, result.points_in_receiver, {"aar-analyze reference model '" + result.name + "'"});
  std::printf("%s model: %zu points -> %s\n", result.name.c_str(), result.points_in_receiver.size(), out.c_str());
  return 0;
}

int RunRunOrBench(int argc, char** argv, bool bench) {
  CLI::App app{bench ? "time the pipeline stages per frame (median, one core); writes nothing"
                     : "analyze every frame (or a selection) and summarise per region",
               bench ? "aar-analyze bench" : "aar-analyze run"};
  RunFlags flags;
  flags.Add(&app);
  if (!bench) {
    app.add_option("--out", flags.options.out, "output folder (default: results/<dataset>-<model>)");
    flags.AddDump(&app);
  }
  if (const auto code = Parse(app, argc, argv)) return *code;
  flags.Resolve();
  if (bench) {
    flags.options.write_outputs = false;
    flags.options.frame.compare_with_truth = false;  // time the pipeline, not the measurement
    flags.options.yardstick_frames = 20;
  }
  const aar::AnalysisRunResult result = aar::RunAnalysis(flags.options);
  const size_t failed =
      std::count_if(result.frames.begin(), result.frames.end(), [](const aar::FrameResult& r) { return !r.ok(); });
  std::fprintf(stderr, "%zu frames analyzed, %zu not measured%s%s\n", result.frames.size(), failed,
               bench ? "" : "; results in ", bench ? "" : flags.options.out.c_str());
  if (bench) PrintStageMedians(result.frames, result.yardstick_ms);
  return 0;
}

int RunRun(int argc, char** argv) { return RunRunOrBench(argc, argv, false); }
int RunBench(int argc, char** argv) { return RunRunOrBench(argc, argv, true); }

int RunMerge(int argc, char** argv) {
  CLI::App app{"combine the outputs of shard runs into one summary", "aar-analyze merge"};
  std::vector<std::filesystem::path> inputs;
  std::filesystem::path out;
  app.add_option("shards", inputs, "run folders of the shards")->required()->check(CLI::ExistingDirectory);
  app.add_option("--out", out, "output folder")->required();
  if (const auto code = Parse(app, argc, argv)) return *code;
  aar::MergeRuns(inputs, out);
  std::fprintf(stderr, "merged %zu shards into %s\n", inputs.size(), out.c_str());
  return 0;
}

int RunExport(int argc, char** argv) {
  CLI::App app{"write a dataset in another tool's format (docs/dataset-format.md, Exports)", "aar-analyze export"};
  aar::ExportOptions options;
  std::string format, frames;
  std::filesystem::path run;
  app.add_option("dataset", options.dataset, "dataset folder")->required();
  std::string formats;
  for (const aar::Exporter& e : aar::Exporters()) {
    formats += std::string(formats.empty() ? "" : ", ") + e.format + " (" + e.description + ")";
  }
  app.add_option("--format", format, formats)->required();
  app.add_option("--out", options.out, "output folder (created)")->required();
  app.add_option("--frames", frames, "half-open range a:b of frame indices (default: all)");
  app.add_option(
      "--run", run,
      aar::ExporterFormats(true) + ": an `aar-analyze run` folder of this dataset; writes its estimates too");
  if (const auto code = Parse(app, argc, argv)) return *code;
  const aar::Exporter& exporter = aar::FindExporter(format);
  options.selection = aar::ParseFrameSelection(frames, "0/1");  // one output: never sharded by Slurm variables
  if (!run.empty()) options.run = run;
  const aar::ExportResult result = aar::ExportDataset(exporter, options);
  for (const std::string& note : result.notes) std::fprintf(stderr, "note: %s\n", note.c_str());
  std::fprintf(stderr, "%s: %zu frames, %zu files in %s\n", exporter.format, result.frames, result.files.size(),
               options.out.c_str());
  return 0;
}

struct Command {
  const char* name;
  int (*run)(int argc, char** argv);
  const char* help;
};

constexpr Command kCommands[] = {
    {"calibrate", RunCalibrate, "stereo calibration from DATASET/calib (thesis 3.3)"},
    {"reference", RunReference, "build a reference point cloud (full or shelled) and write it as PLY"},
    {"run", RunRun, "analyze every frame (or a selection) and summarise per region"},
    {"bench", RunBench, "time the pipeline stages per frame (median, one core); writes nothing"},
    {"merge", RunMerge, "combine the outputs of shard runs into one summary"},
    {"export", RunExport, "write a dataset as BOP, Middlebury, TUM trajectories, ROS CameraInfo or a ROS bag"},
};

void PrintUsage(FILE* out) {
  std::fprintf(out,
               "aar-analyze: calibrates the stereo pair, computes disparity, re-projects and registers a reference "
               "model with ICP over a saved dataset; writes per-frame CSV and per-region statistics "
               "(docs/analysis.md).\n\nUsage: aar-analyze COMMAND [OPTIONS]   (aar-analyze COMMAND --help for its "
               "options)\n       aar-analyze --version\n\nCommands:\n");
  for (const Command& c : kCommands) std::fprintf(out, "  %-10s %s\n", c.name, c.help);
}

}  // namespace

int main(int argc, char** argv) {
  cv::setNumThreads(1);  // one core, deterministic (docs/performance.md)
  if (argc < 2 || std::strcmp(argv[1], "--help") == 0 || std::strcmp(argv[1], "-h") == 0) {
    PrintUsage(argc < 2 ? stderr : stdout);
    return argc < 2 ? 1 : 0;
  }
  if (std::strcmp(argv[1], "--version") == 0) {
    std::printf("aar-analyze %s (git %s)\n", AAR_VERSION, AAR_GIT_HASH);
    return 0;
  }
  for (const Command& c : kCommands) {
    if (std::strcmp(argv[1], c.name) != 0) continue;
    try {
      return c.run(argc - 1, argv + 1);
    } catch (const aar::Error& e) {
      std::fprintf(stderr, "aar-analyze: error: %s\n", e.what());
      return 1;
    } catch (const std::filesystem::filesystem_error& e) {
      std::fprintf(stderr, "aar-analyze: error: %s\n", aar::FileSystemMessage(e).c_str());
      return 1;
    } catch (const std::exception& e) {
      std::fprintf(stderr, "aar-analyze: internal error: %s\n", e.what());
      return 2;
    }
  }
  std::fprintf(stderr, "aar-analyze: error: unknown command '%s'\n\n", argv[1]);
  PrintUsage(stderr);
  return 1;
}
