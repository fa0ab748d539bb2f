// aar-analyze: offline analysis of AAR stereo datasets (thesis sections
// 3.3-3.7). A thin table of subcommands; the work lives in aar_analyzer.

#include <algorithm>
#include <cstdio>
#include <filesystem>

#include <CLI/CLI.hpp>
#include <opencv2/core.hpp>

#include "aar/analyzer/analysis_run.h"
#include "aar/analyzer/mesh.h"
#include "aar/error.h"
#include "aar/file_io.h"

namespace {

struct RunFlags {
  aar::AnalysisRunOptions options;
  std::string calibration;
  std::string receiver;
  std::string frames;
  std::string shard;
  std::string seed = "centroid";
  std::string correspondence = aar::ToString(aar::FrameAnalysisOptions{}.icp.correspondence);
  std::string disparity = "bm";
};

void AddRunFlags(CLI::App* cmd, RunFlags& f) {
  aar::AnalysisRunOptions& o = f.options;
  cmd->add_option("dataset", o.dataset, "dataset folder")->required();
  cmd->add_option("--model", o.reference.model, "reference model: full or shelled")->capture_default_str();
  cmd->add_option("--calibration", f.calibration,
                  "OpenCV YAML calibration to use (default: calibrate from DATASET/calib first)");
  cmd->add_option("--receiver", f.receiver, "receiver glTF (default: DATASET/receiver.glb)");
  cmd->add_option("--frames", f.frames, "half-open range a:b of frame indices");
  cmd->add_option("--shard", f.shard, "analyze frames i with i % N == K (K/N); defaults to the Slurm array variables");
  cmd->add_option("--seed", f.seed, "ICP seed: centroid (thesis) or previous (last frame's estimate)")
      ->capture_default_str();
  cmd->add_option("--correspondence", f.correspondence, "ICP pairing: sensed_to_model or model_to_sensed")
      ->capture_default_str();
  cmd->add_option("--icp-iterations", o.frame.icp.max_iterations, "ICP iterations at most")->capture_default_str();
  cmd->add_option("--max-correspondence", o.frame.icp.max_correspondence_distance_m,
                  "ICP pairs farther apart are ignored [m] (default: none, as in the thesis)");
  cmd->add_option("--max-residual", o.frame.max_icp_rmse_m,
                  "ICP residual allowance at zero range [m]; 3 sigma of the expected stereo depth noise is added")
      ->capture_default_str();
  cmd->add_option("--disparity", f.disparity, "bm (StereoBM, thesis) or sgbm")->capture_default_str();
  cmd->add_option("--num-disparities", o.frame.disparity.num_disparities, "disparities searched")
      ->capture_default_str();
  cmd->add_option("--block-size", o.frame.disparity.block_size, "matching block size [px]")->capture_default_str();
  cmd->add_option("--disparity-offset", o.frame.reprojection.disparity_offset_px,
                  "subtracted from every disparity before re-projection [px] (0 = thesis)")
      ->capture_default_str();
  cmd->add_option("--keep-one-in", o.frame.reprojection.keep_one_in, "keep one re-projected point in N")
      ->capture_default_str();
  cmd->add_option("--points", o.reference.options.num_points, "full-model points")->capture_default_str();
  cmd->add_flag("--no-progress", [&f](int64_t) { f.options.progress = false; }, "quiet stderr");
}

void Resolve(RunFlags& f) {
  aar::AnalysisRunOptions& o = f.options;
  if (!f.calibration.empty()) o.calibration = f.calibration;
  if (!f.receiver.empty()) o.receiver_model = f.receiver;
  o.selection = aar::ParseFrameSelection(f.frames, f.shard);
  o.frame.seed = aar::ParseIcpSeed(f.seed);
  o.frame.icp.correspondence = aar::ParseIcpCorrespondence(f.correspondence);
  if (f.disparity == "bm") {
    o.frame.disparity.algorithm = aar::DisparityAlgorithm::kBlockMatching;
  } else if (f.disparity == "sgbm") {
    o.frame.disparity.algorithm = aar::DisparityAlgorithm::kSemiGlobal;
  } else {
    throw aar::Error("--disparity '" + f.disparity + "': expected bm or sgbm");
  }
}

double Median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

void PrintStageMedians(const std::vector<aar::FrameResult>& frames) {
  std::vector<double> load, rectify, disparity, reproject, icp, total;
  for (const aar::FrameResult& f : frames) {
    if (!f.ok()) continue;
    load.push_back(f.times.load_ms);
    rectify.push_back(f.times.rectify_ms);
    disparity.push_back(f.times.disparity_ms);
    reproject.push_back(f.times.reproject_ms);
    icp.push_back(f.times.icp_ms);
    total.push_back(f.times.total_ms);
  }
  std::printf("| frames | load ms | rectify ms | disparity ms | reproject ms | ICP ms | total ms |\n");
  std::printf("|---|---|---|---|---|---|---|\n");
  std::printf("| %zu | %.1f | %.1f | %.1f | %.1f | %.1f | %.1f |\n", total.size(), Median(load), Median(rectify),
              Median(disparity), Median(reproject), Median(icp), Median(total));
}

std::string DatasetName(const std::filesystem::path& dataset) {
  const std::filesystem::path clean = dataset.lexically_normal();
  return (clean.has_filename() ? clean.filename() : clean.parent_path().filename()).string();
}

}  // namespace

int main(int argc, char** argv) {
  cv::setNumThreads(1);  // one core, deterministic (docs/performance.md)
  CLI::App app{
      "aar-analyze: calibrates the stereo pair, computes disparity, re-projects and registers a reference model "
      "with ICP over a saved dataset; writes per-frame CSV and per-region statistics (docs/analysis.md)."};
  app.require_subcommand(1);

  std::filesystem::path calib_dataset, calib_out;
  aar::CalibrationOptions calib_options;
  CLI::App* calibrate = app.add_subcommand("calibrate", "stereo calibration from DATASET/calib (thesis 3.3)");
  calibrate->add_option("dataset", calib_dataset, "dataset folder")->required();
  calibrate->add_option("--out", calib_out, "output folder (default: results/<dataset>-calibration)");
  calibrate->add_flag("--estimate-distortion", [&](int64_t) { calib_options.fix_distortion = false; },
                      "also estimate k1 k2 p1 p2 k3 (the renderer has none)");

  std::string ref_model = "shelled", ref_receiver = "scenes/c12.glb", ref_rig = "scenes/rig.json", ref_out;
  aar::ReferenceModelOptions ref_options;
  CLI::App* reference = app.add_subcommand("reference", "build a reference point cloud and write it as PLY");
  reference->add_option("--model", ref_model, "full or shelled")->capture_default_str();
  reference->add_option("--receiver", ref_receiver, "receiver glTF")->capture_default_str();
  reference->add_option("--rig", ref_rig, "camera rig (shelling uses its contact position)")->capture_default_str();
  reference->add_option("--points", ref_options.num_points, "full-model points")->capture_default_str();
  reference->add_option("--out", ref_out, "PLY file (default: reference_<model>.ply)");

  RunFlags run_flags;
  CLI::App* run = app.add_subcommand("run", "analyze every frame (or a selection) and summarise per region");
  AddRunFlags(run, run_flags);
  run->add_option("--out", run_flags.options.out, "output folder (default: results/<dataset>-<model>)");

  RunFlags bench_flags;
  CLI::App* bench = app.add_subcommand("bench", "time the pipeline stages per frame (median, one core); writes nothing");
  AddRunFlags(bench, bench_flags);

  std::vector<std::filesystem::path> merge_inputs;
  std::filesystem::path merge_out;
  CLI::App* merge = app.add_subcommand("merge", "combine the outputs of shard runs into one summary");
  merge->add_option("shards", merge_inputs, "run folders of the shards")->required()->check(CLI::ExistingDirectory);
  merge->add_option("--out", merge_out, "output folder")->required();

  CLI11_PARSE(app, argc, argv);
  try {
    if (calibrate->parsed()) {
      if (calib_out.empty()) calib_out = std::filesystem::path("results") / (DatasetName(calib_dataset) + "-calibration");
      const aar::CalibrateOutput out = aar::CalibrateDataset(calib_dataset, calib_options);
      aar::WriteCalibrationOutputs(calib_out, out);
      std::printf("%s\nwrote %s and %s\n", out.result.BriefReport().c_str(),
                  (calib_out / aar::kCalibrationYamlName).c_str(), (calib_out / aar::kCalibrationReportName).c_str());
    } else if (reference->parsed()) {
      const aar::TriangleMesh mesh = aar::LoadReceiverMesh(ref_receiver);
      const aar::StereoRig rig = aar::LoadRig(ref_rig);
      const aar::ReferenceModel model = aar::BuildReferenceModel(mesh, rig, {ref_model, ref_options});
      if (ref_out.empty()) ref_out = "reference_" + model.name + ".ply";
      aar::WritePly(ref_out, model.points_in_receiver, {"aar-analyze reference model '" + model.name + "'"});
      std::printf("%s model: %zu points -> %s\n", model.name.c_str(), model.points_in_receiver.size(), ref_out.c_str());
    } else if (run->parsed() || bench->parsed()) {
      RunFlags& f = run->parsed() ? run_flags : bench_flags;
      Resolve(f);
      if (bench->parsed()) f.options.write_outputs = false;
      if (f.options.out.empty()) {
        f.options.out = std::filesystem::path("results") / (DatasetName(f.options.dataset) + "-" + f.options.reference.model);
      }
      const aar::AnalysisRunResult result = aar::RunAnalysis(f.options);
      const size_t failed = std::count_if(result.frames.begin(), result.frames.end(),
                                          [](const aar::FrameResult& r) { return !r.ok(); });
      std::fprintf(stderr, "%zu frames analyzed, %zu not measured%s%s\n", result.frames.size(), failed,
                   f.options.write_outputs ? "; results in " : "",
                   f.options.write_outputs ? f.options.out.c_str() : "");
      if (bench->parsed()) PrintStageMedians(result.frames);
    } else if (merge->parsed()) {
      aar::MergeRuns(merge_inputs, merge_out);
      std::fprintf(stderr, "merged %zu shards into %s\n", merge_inputs.size(), merge_out.c_str());
    }
  } catch (const aar::Error& e) {
    std::fprintf(stderr, "aar-analyze: error: %s\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "aar-analyze: internal error: %s\n", e.what());
    return 2;
  }
  return 0;
}
