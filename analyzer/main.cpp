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

namespace {

// The dataset folder's own name ("." and "dir/" name the folder they mean).
std::string DatasetName(const std::filesystem::path& dataset) {
  std::error_code ec;
  std::filesystem::path clean = std::filesystem::weakly_canonical(std::filesystem::absolute(dataset, ec), ec);
  if (ec) clean = dataset.lexically_normal();
  return (clean.has_filename() ? clean.filename() : clean.parent_path().filename()).string();
}

// Reference-model flags shared by `reference`, `run` and `bench`.
struct ReferenceFlags {
  std::string shell = "strict";
  std::optional<std::string> cameras;
  std::optional<double> tolerance_m;
  size_t points = aar::ReferenceModelOptions{}.num_points;

  void Add(CLI::App* cmd) {
    cmd->add_option("--shell", shell,
                    "shelling rule: strict (both cameras, own pixel, 1 cm, >= 15 deg from grazing) "
                    "or loose (the first version's: either camera, 3x3 window, 5 cm)")
        ->capture_default_str();
    cmd->add_option("--shell-cameras", cameras, "cameras that must see a shell point: left, either or both");
    cmd->add_option("--shell-tolerance", tolerance_m, "shell depth-test tolerance [m]");
    cmd->add_option("--points", points, "full-model points")->capture_default_str();
  }
  aar::ReferenceModelOptions Resolve() const {
    aar::ReferenceModelOptions o;
    if (shell == "loose") {
      o = aar::ReferenceModelOptions::Loose();
    } else if (shell != "strict") {
      throw aar::Error("--shell '" + shell + "': expected strict or loose");
    }
    o.num_points = points;
    if (cameras) o.cameras = aar::ParseShellCameras(*cameras);
    if (tolerance_m) o.depth_tolerance_m = *tolerance_m;
    o.Check();
    return o;
  }
};

// Flags of `run` and `bench`. Values a preset sets are optional: given, they
// override the preset.
struct RunFlags {
  aar::AnalysisRunOptions options;
  ReferenceFlags reference;
  std::string preset = "default";
  std::string calibration, receiver, frames, shard, disparity = "bm";
  std::optional<std::string> subpixel_window;
  std::optional<std::string> subpixel_interpolation;
  std::optional<bool> window_bias;
  std::optional<std::string> seed, registration, correspondence, pairing, residual;
  std::optional<int> icp_iterations, num_disparities, block_size, halo_radius, uniqueness_ratio, speckle_window;
  std::optional<double> max_correspondence_m, disparity_offset_px, disparity_noise_px, gate_sigmas, model_pull_scale_m;
  std::optional<size_t> keep_one_in, target_points, model_queries;
  std::optional<bool> halo, subpixel, rounding, widen, balance, full_surface, noise_bias;
  bool truth_cloud = false, track = false, mask_boom = false, no_mask_boom = false, mask_propellers = false,
       no_mask_propellers = false;
  double truth_cloud_noise_px = 0.0;
  int boom_margin_px = aar::BoomMaskOptions{}.margin_px;
  std::vector<size_t> dump_frames;

  void Add(CLI::App* cmd) {
    aar::AnalysisRunOptions& o = options;
    cmd->add_option("dataset", o.dataset, "dataset folder")->required();
    cmd->add_option("--preset", preset,
                    "pipeline: default (halo removal, BM rounding correction, "
                    "robust noise-weighted point-to-plane ICP) or thesis (Parsons 2017)")
        ->capture_default_str();
    cmd->add_option("--model", o.reference.model, "reference model: full or shelled")->capture_default_str();
    reference.Add(cmd);
    cmd->add_option("--calibration", calibration,
                    "OpenCV YAML calibration to use (default: calibrate from DATASET/calib first)");
    cmd->add_option("--receiver", receiver, "receiver glTF (default: DATASET/receiver.glb)");
    cmd->add_option("--frames", frames, "half-open range a:b of frame indices");
    cmd->add_option("--shard", shard, "analyze frames i with i % N == K (K/N); defaults to the Slurm array variables");
    cmd->add_option("--seed", seed,
                    "ICP seed: centroid (thesis) or previous (the last estimate; from the centroid again after a "
                    "failure or an attitude beyond 15 deg)");
    cmd->add_option("--registration", registration, "point_to_plane (default preset) or point_to_point (thesis)");
    cmd->add_option("--correspondence", correspondence,
                    "point-to-point pairing: model_to_sensed (thesis) or sensed_to_model");
    cmd->add_option("--pairing", pairing,
                    "point-to-plane pairing: mahalanobis (default: each sensed point with the camera-facing model "
                    "point nearest in the stereo noise metric), symmetric (nearest in metres, plus model-to-sensed "
                    "pairs), or sensed_to_model");
    cmd->add_option("--residual", residual,
                    "point-to-plane residual of a sensed point: metric (default: its distance to the model's tangent "
                    "plane in metres), disparity (along its own ray, in disparity: the model's predicted minus the "
                    "measured) or metric-ray (metric, the rotation turning it about where its ray meets the tangent "
                    "plane, not about the noisy point)");
    cmd->add_option("--full-surface", full_surface,
                    "point-to-plane with the shelled model: pair sensed points with the full model's surface");
    cmd->add_option("--balance", balance, "symmetric pairing: weigh both directions equally in total (default: false)");
    cmd->add_option(
        "--gate-sigmas", gate_sigmas,
        "point-to-plane: pairs beyond this many along-ray sigmas (or --max-correspondence) are ignored (3)");
    cmd->add_option("--model-pull-scale", model_pull_scale_m,
                    "symmetric pairing: model-to-sensed pairs weigh s^2 / (s^2 + t^2), s their along-ray sigma, t this "
                    "[m] (0.5; 0 = always fully)");
    cmd->add_option("--model-queries", model_queries,
                    "symmetric pairing: model points that query the cloud per iteration, at most (4000; 0 = all)");
    cmd->add_option("--icp-iterations", icp_iterations, "ICP iterations at most (thesis 30, default 60)");
    cmd->add_option("--max-correspondence", max_correspondence_m,
                    "ICP pairs farther apart are ignored [m] (thesis: none; default 2)");
    cmd->add_option("--max-residual", o.frame.max_icp_rmse_m,
                    "ICP residual allowance at zero range [m]; 3 sigma of the expected stereo depth noise is added")
        ->capture_default_str();
    cmd->add_option("--disparity", disparity, "bm (StereoBM, thesis) or sgbm")->capture_default_str();
    cmd->add_option("--num-disparities", num_disparities, "disparities searched (48)");
    cmd->add_option("--block-size", block_size, "matching block size [px] (9)");
    cmd->add_option("--uniqueness-ratio", uniqueness_ratio,
                    "block matching: the best cost must beat the second best by this many percent (15)");
    cmd->add_option("--speckle-window", speckle_window,
                    "speckle filter: connected disparity regions smaller than this are removed [px] (100; 0: off)");
    cmd->add_option("--halo", halo, "remove the block-matching halo around the silhouette (default preset: true)");
    cmd->add_option("--halo-radius", halo_radius,
                    "halo removal: valid pixels this close to an invalid pixel or a jump go [px] (block / 2 + 1)");
    cmd->add_option("--rounding", rounding, "subtract StereoBM's 15/512 px rounding bias (default preset: true)");
    cmd->add_option("--subpixel", subpixel,
                    "symmetric sub-pixel refinement of every kept disparity (default preset: true, thesis: false)");
    cmd->add_option("--subpixel-window", subpixel_window,
                    "sub-pixel window: slanted (default: follows the surface's disparity slope) or flat (one shift)");
    cmd->add_option(
        "--subpixel-interpolation", subpixel_interpolation,
        "sub-pixel sampling: linear (default) or bspline (Gaussian-prefiltered cubic B-spline of each row)");
    cmd->add_option("--window-bias", window_bias,
                    "subtract each refined disparity's window bias predicted on the model at the registered pose, "
                    "and register again (default: false)");
    cmd->add_option("--widen-search", widen, "match near frames again with a wider disparity search (default: true)");
    cmd->add_option("--disparity-offset", disparity_offset_px,
                    "also subtracted from every disparity, refined or not [px] (0)");
    cmd->add_option("--disparity-noise", disparity_noise_px, "disparity noise of the ICP noise model [px] (0.1)");
    cmd->add_option("--noise-bias-correction", noise_bias,
                    "point-to-plane, metric residual: after convergence, one step removing the rotation bias of the "
                    "sensed points' noise, scaled to the frame's residuals (default: false)");
    cmd->add_option("--keep-one-in", keep_one_in, "keep one re-projected point in N (8)");
    cmd->add_option("--target-points", target_points,
                    "raise the decimation so that about this many points remain (default preset 4000; 0 = off)");
    cmd->add_flag("--track", track,
                  "match only where the receiver is predicted from the last two frames (whole image when lost)");
    cmd->add_option("--filter-window", o.filter.window_s,
                    "temporal filter: at each frame, a constant-velocity line through the estimates of the last S "
                    "seconds, read at the frame's time (frames.csv's filt_* columns; docs/analysis.md) [s]")
        ->capture_default_str()
        ->check(CLI::NonNegativeNumber);
    cmd->add_flag("--mask-boom", mask_boom,
                  "remove the boom's pixels before re-projection, drawn from the sidecar's boom angles and the rig "
                  "(default preset: on for datasets with the boom)")
        ->excludes(cmd->add_flag("--no-mask-boom", no_mask_boom, "keep the boom's pixels"));
    cmd->add_option("--boom-margin", boom_margin_px, "the boom mask: grow the drawn boom by this many pixels")
        ->capture_default_str();
    cmd->add_flag("--mask-propellers", mask_propellers,
                  "drop the sensed points inside the receiver's two propeller discs under the registered pose and "
                  "register again, up to three times (default preset: on for datasets whose propellers turn)")
        ->excludes(cmd->add_flag("--no-mask-propellers", no_mask_propellers, "keep the propellers' points"));
    cmd->add_option("--truth-cloud-noise", truth_cloud_noise_px,
                    "diagnosis, with --truth-cloud: seeded Gaussian disparity noise along each ideal point's ray [px]")
        ->capture_default_str();
    cmd->add_flag("--truth-cloud", truth_cloud,
                  "diagnosis: register the ideal cloud (depth truth at the sensed pixels; datasets with --depth)");
    cmd->add_flag(
        "--no-progress", [this](int64_t) { options.progress = false; }, "quiet stderr");
  }
  // `run` only: per listed frame, disparity, clouds and overlay into OUT/frames/.
  void AddDump(CLI::App* cmd) {
    cmd->add_option("--dump-frames", dump_frames,
                    "frame indices (comma-separated) whose colour-mapped disparity, sensed cloud, registered model "
                    "(PLY) and overlay on the left image are written into OUT/frames/")
        ->delimiter(',');
  }

  void Resolve() {
    aar::AnalysisRunOptions& o = options;
    const double max_residual = o.frame.max_icp_rmse_m;
    o.preset = aar::ParsePreset(preset);
    o.frame = aar::FrameAnalysisOptions::ForPreset(o.preset);
    o.frame.max_icp_rmse_m = max_residual;
    o.reference.options = reference.Resolve();
    if (!calibration.empty()) o.calibration = calibration;
    if (!receiver.empty()) o.receiver_model = receiver;
    o.selection = aar::ParseFrameSelection(frames, shard);
    aar::FrameAnalysisOptions& f = o.frame;
    if (disparity == "bm") {
      f.disparity.algorithm = aar::DisparityAlgorithm::kBlockMatching;
    } else if (disparity == "sgbm") {
      f.disparity.algorithm = aar::DisparityAlgorithm::kSemiGlobal;
    } else {
      throw aar::Error("--disparity '" + disparity + "': expected bm or sgbm");
    }
    if (seed) f.seed = aar::ParseIcpSeed(*seed);
    if (registration) f.registration = aar::ParseRegistration(*registration);
    if (correspondence) f.icp.correspondence = aar::ParseIcpCorrespondence(*correspondence);
    if (pairing) f.plane_icp.pairing = aar::ParsePlanePairing(*pairing);
    if (residual) f.plane_icp.residual = aar::ParsePlaneResidual(*residual);
    if (icp_iterations) f.icp.max_iterations = f.plane_icp.max_iterations = *icp_iterations;
    if (max_correspondence_m)
      f.icp.max_correspondence_distance_m = f.plane_icp.max_correspondence_distance_m = *max_correspondence_m;
    if (num_disparities) f.disparity.num_disparities = *num_disparities;
    if (uniqueness_ratio) f.disparity.uniqueness_ratio = *uniqueness_ratio;
    if (speckle_window) f.disparity.speckle_window_size = *speckle_window;
    if (block_size) {
      f.disparity.block_size = *block_size;
      f.halo.radius_px = aar::HaloRadiusPx(f.disparity);
      f.subpixel.half_window_px = *block_size / 2;
    }
    if (halo) f.remove_halo = *halo;
    if (halo_radius) f.halo.radius_px = *halo_radius;
    if (rounding) f.remove_rounding_bias = *rounding;
    if (subpixel) f.refine_subpixel = *subpixel;
    if (subpixel_window) {
      if (*subpixel_window != "slanted" && *subpixel_window != "flat") {
        throw aar::Error("--subpixel-window '" + *subpixel_window + "': expected slanted or flat");
      }
      f.subpixel.slanted = *subpixel_window == "slanted";
    }
    if (subpixel_interpolation) f.subpixel.interpolation = aar::ParseSubpixelInterpolation(*subpixel_interpolation);
    if (window_bias) f.correct_window_bias = *window_bias;
    if (widen) f.widen_disparity_search = *widen;
    if (balance) f.plane_icp.balance_directions = *balance;
    if (noise_bias) f.plane_icp.noise_bias_correction = *noise_bias;
    if (gate_sigmas) f.plane_icp.gate_sigmas = *gate_sigmas;
    if (full_surface) f.pair_sensed_with_full_surface = *full_surface;
    if (model_queries) f.plane_icp.max_model_queries = *model_queries;
    if (model_pull_scale_m) f.plane_icp.model_pull_scale_m = *model_pull_scale_m;
    if (disparity_offset_px) f.reprojection.disparity_offset_px = *disparity_offset_px;
    if (disparity_noise_px) f.plane_icp.disparity_noise_px = f.disparity_noise_px = *disparity_noise_px;
    if (keep_one_in) f.reprojection.keep_one_in = *keep_one_in;
    if (target_points) f.reprojection.target_points = *target_points;
    f.register_truth_cloud = truth_cloud;
    f.truth_cloud_noise_px = truth_cloud_noise_px;
    f.track_region = track;
    if (mask_boom || no_mask_boom) o.mask_boom = mask_boom;
    f.boom_mask.margin_px = boom_margin_px;
    if (mask_propellers || no_mask_propellers) o.mask_propellers = mask_propellers;
    f.Check();
    o.dump_frames = dump_frames;
    // Shards (Slurm array tasks) get folders of their own, never one another's.
    if (o.out.empty()) {
      o.out = std::filesystem::path("results") /
              (DatasetName(o.dataset) + "-" + o.reference.model + o.selection.ShardSuffix());
    }
  }
};

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
  const aar::CalibrateOutput result = aar::CalibrateDataset(dataset, options);
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
