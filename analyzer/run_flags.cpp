#include "run_flags.h"

#include "aar/analyzer/options_record.h"
#include "aar/analyzer/run_record.h"
#include "aar/error.h"

namespace aar::cli {

std::string DatasetName(const std::filesystem::path& dataset) {
  std::error_code ec;
  std::filesystem::path clean = std::filesystem::weakly_canonical(std::filesystem::absolute(dataset, ec), ec);
  if (ec) clean = dataset.lexically_normal();
  return (clean.has_filename() ? clean.filename() : clean.parent_path().filename()).string();
}

void ReferenceFlags::Add(CLI::App* cmd) {
  cmd->add_option("--shell", shell,
                  "shelling rule: strict (both cameras, own pixel, 1 cm, >= 15 deg from grazing) "
                  "or loose (the first version's: either camera, 3x3 window, 5 cm)")
      ->capture_default_str();
  cmd->add_option("--shell-cameras", cameras, "cameras that must see a shell point: left, either or both");
  cmd->add_option("--shell-tolerance", tolerance_m, "shell depth-test tolerance [m]");
  cmd->add_option("--points", points, "full-model points")->capture_default_str();
}

aar::ReferenceModelOptions ReferenceFlags::Resolve() const {
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

void RunFlags::Add(CLI::App* command) {
  cmd = command;
  aar::AnalysisRunOptions& o = options;
  cmd->add_option("dataset", o.dataset, "dataset folder")->required();
  cmd->add_option("--options-from", options_from,
                  "a run folder: analyse with the options its run.json records (preset, every stage's settings, "
                  "reference model, masks, filter) to reproduce it; only the dataset, --calibration, --receiver, "
                  "--frames, --shard and the output flags may be given beside it");
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
  AddRegistration(cmd);
  AddStereo(cmd);
  AddMasksAndDiagnosis(cmd);
}

void RunFlags::AddRegistration(CLI::App* cmd) {
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
  cmd->add_option("--gate-sigmas", gate_sigmas,
                  "point-to-plane: pairs beyond this many along-ray sigmas (or --max-correspondence) are ignored (3)");
  cmd->add_option("--model-pull-scale", model_pull_scale_m,
                  "symmetric pairing: model-to-sensed pairs weigh s^2 / (s^2 + t^2), s their along-ray sigma, t this "
                  "[m] (0.5; 0 = always fully)");
  cmd->add_option("--model-queries", model_queries,
                  "symmetric pairing: model points that query the cloud per iteration, at most (4000; 0 = all)");
  cmd->add_option("--icp-iterations", icp_iterations, "ICP iterations at most (thesis 30, default 60)");
  cmd->add_option("--max-correspondence", max_correspondence_m,
                  "ICP pairs farther apart are ignored [m] (thesis: none; default 2)");
  cmd->add_option("--max-residual", options.frame.max_icp_rmse_m,
                  "ICP residual allowance at zero range [m]; 3 sigma of the expected stereo depth noise is added")
      ->capture_default_str();
  cmd->add_option("--noise-bias-correction", noise_bias,
                  "point-to-plane, metric residual: after convergence, one step removing the rotation bias of the "
                  "sensed points' noise, scaled to the frame's residuals (default: false)");
}

void RunFlags::AddStereo(CLI::App* cmd) {
  cmd->add_option("--disparity", disparity, "bm (StereoBM, thesis) or sgbm")->capture_default_str();
  cmd->add_option("--num-disparities", num_disparities, "disparities searched (48)");
  cmd->add_option("--block-size", block_size, "matching block size [px] (9)");
  cmd->add_option("--uniqueness-ratio", uniqueness_ratio,
                  "block matching: the best cost must beat the second best by this many percent (15)");
  cmd->add_option("--speckle-window", speckle_window,
                  "speckle filter: connected disparity regions smaller than this are removed [px] (100; 0: off)");
  cmd->add_option("--halo", halo, "remove the block-matching halo around the silhouette (default preset: true)");
  cmd->add_option("--clipped", clipped,
                  "drop matches whose window reaches a clipped (white, 255) pixel in either image: sun glints, a "
                  "saturated sensor (default: false)");
  cmd->add_option("--halo-radius", halo_radius,
                  "halo removal: valid pixels this close to an invalid pixel or a jump go [px] (block / 2 + 1)");
  cmd->add_option("--rounding", rounding, "subtract StereoBM's 15/512 px rounding bias (default preset: true)");
  cmd->add_option("--subpixel", subpixel,
                  "symmetric sub-pixel refinement of every kept disparity (default preset: true, thesis: false)");
  cmd->add_option("--subpixel-window", subpixel_window,
                  "sub-pixel window: slanted (default: follows the surface's disparity slope) or flat (one shift)");
  cmd->add_option("--subpixel-interpolation", subpixel_interpolation,
                  "sub-pixel sampling: linear (default) or bspline (Gaussian-prefiltered cubic B-spline of each row)");
  cmd->add_option("--window-bias", window_bias,
                  "subtract each refined disparity's window bias predicted on the model at the registered pose, "
                  "and register again (default: false)");
  cmd->add_option("--direct-stereo", direct,
                  "after registration, fit the pose to the rectified images at the model's disparities: "
                  "off, translation (keep the registration's rotation) or pose (default: off)");
  cmd->add_option("--direct-max-motion", direct_max_motion_px,
                  "--direct-stereo: a fit that moves the model's bounding box by more than this in the images is "
                  "not applied [px] (2)");
  cmd->add_option("--widen-search", widen, "match near frames again with a wider disparity search (default: true)");
  cmd->add_option("--disparity-offset", disparity_offset_px,
                  "also subtracted from every disparity, refined or not [px] (0)");
  cmd->add_option("--disparity-noise", disparity_noise_px, "disparity noise of the ICP noise model [px] (0.1)");
  cmd->add_option("--keep-one-in", keep_one_in, "keep one re-projected point in N (8)");
  cmd->add_option("--target-points", target_points,
                  "raise the decimation so that about this many points remain (default preset 4000; 0 = off)");
}

void RunFlags::AddMasksAndDiagnosis(CLI::App* cmd) {
  aar::AnalysisRunOptions& o = options;
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

void RunFlags::AddDump(CLI::App* cmd) {
  cmd->add_option("--dump-frames", dump_frames,
                  "frame indices (comma-separated) whose colour-mapped disparity, sensed cloud, registered model "
                  "(PLY) and overlay on the left image are written into OUT/frames/")
      ->delimiter(',');
}

namespace {

// The flags that choose what is analysed and where the results go, not how: allowed beside --options-from.
bool SelectsInputOrOutput(const std::string& name) {
  for (const char* flag : {"dataset", "--options-from", "--calibration", "--receiver", "--frames", "--shard", "--out",
                           "--no-progress", "--dump-frames", "--help"}) {
    if (name == flag) return true;
  }
  return false;
}

}  // namespace

void RunFlags::ApplyOptionsFrom() {
  for (const CLI::Option* option : cmd->get_options()) {
    if (option->count() > 0 && !SelectsInputOrOutput(option->get_name())) {
      throw aar::Error(option->get_name() +
                       ": not with --options-from, which takes the analysis options "
                       "from " +
                       options_from + "'s run.json");
    }
  }
  const nlohmann::json run = aar::ReadRunJson(options_from);
  aar::ApplyRecordedOptions(run.at("options"), (std::filesystem::path(options_from) / aar::kRunJsonName).string(),
                            options);
}

void RunFlags::Resolve() {
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
    f.clipped.radius_px = aar::HaloRadiusPx(f.disparity);
    f.subpixel.half_window_px = *block_size / 2;
  }
  if (halo) f.remove_halo = *halo;
  if (clipped) f.remove_clipped = *clipped;
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
  if (direct) {
    if (*direct != "off" && *direct != "translation" && *direct != "pose")
      throw aar::Error("--direct-stereo: expected off, translation or pose, not '" + *direct + "'");
    f.refine_direct = *direct != "off";
    if (f.refine_direct) f.direct.fit = aar::ParseDirectStereoFit(*direct);
  }
  if (direct_max_motion_px) f.direct.max_motion_px = *direct_max_motion_px;
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
  if (!options_from.empty()) ApplyOptionsFrom();
  o.dump_frames = dump_frames;
  // Shards (Slurm array tasks) get folders of their own, never one another's.
  if (o.out.empty()) {
    o.out = std::filesystem::path("results") /
            (DatasetName(o.dataset) + "-" + o.reference.model + o.selection.ShardSuffix());
  }
}

}  // namespace aar::cli
