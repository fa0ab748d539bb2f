#include "aar/analyzer/run_record.h"

#include <algorithm>
#include <cmath>

#include "aar/error.h"
#include "aar/file_io.h"

namespace aar {
namespace {

nlohmann::json Finite(double value) { return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json("inf"); }

nlohmann::json RegistrationJson(const FrameAnalysisOptions& f) {
  nlohmann::json registration = {{"algorithm", ToString(f.registration)},
                                 {"seed", ToString(f.seed)},
                                 {"track_region", f.track_region},
                                 {"min_inlier_fraction", f.min_inlier_fraction}};
  if (f.seed == IcpSeed::kPreviousFrame) registration["max_seed_attitude_deg"] = f.max_seed_attitude_deg;
  if (f.registration == Registration::kPointToPoint) {
    registration.update({{"max_iterations", f.icp.max_iterations},
                         {"correspondence", ToString(f.icp.correspondence)},
                         {"max_correspondence_distance_m", Finite(f.icp.max_correspondence_distance_m)}});
  } else {
    const PlaneIcpOptions& p = f.plane_icp;
    registration.update({{"max_iterations", p.max_iterations},
                         {"pairing", ToString(p.pairing)},
                         {"residual", ToString(p.residual)},
                         {"converged_chi2", p.converged_chi2},
                         {"noise_bias_correction", p.noise_bias_correction},
                         {"sensed_pairing_surface", f.pair_sensed_with_full_surface ? "full" : "model"},
                         {"model_pull_scale_m", p.model_pull_scale_m},
                         {"gate_sigmas", p.gate_sigmas},
                         {"max_model_queries", p.max_model_queries},
                         {"max_correspondence_distance_m", Finite(p.max_correspondence_distance_m)},
                         {"robust_scale", p.robust_scale},
                         {"disparity_noise_px", p.disparity_noise_px},
                         {"lateral_noise_px", p.lateral_noise_px},
                         {"surface_noise_m", p.surface_noise_m}});
  }
  return registration;
}

nlohmann::json DisparityJson(const FrameAnalysisOptions& f) {
  return {
      {"algorithm", f.disparity.algorithm == DisparityAlgorithm::kBlockMatching ? "bm" : "sgbm"},
      {"num_disparities", f.disparity.num_disparities},
      {"block_size", f.disparity.block_size},
      {"uniqueness_ratio", f.disparity.uniqueness_ratio},
      {"speckle_window_size", f.disparity.speckle_window_size},
      {"speckle_range_px", f.disparity.speckle_range_px},
      {"background_disparity_px", f.disparity.background_disparity_px},
      {"halo_radius_px", f.remove_halo ? f.halo.radius_px : 0},
      {"rounding_bias_px", f.remove_rounding_bias ? MatcherRoundingBiasPx(f.disparity.algorithm) : 0.0},
      {"subpixel", f.refine_subpixel ? (f.subpixel.slanted ? "slanted" : "symmetric") : "none"},
      {"subpixel_interpolation", f.subpixel.interpolation == SubpixelInterpolation::kLinear
                                     ? nlohmann::json(ToString(f.subpixel.interpolation))
                                     : nlohmann::json{{"kind", ToString(f.subpixel.interpolation)},
                                                      {"prefilter_sigma_px", f.subpixel.prefilter_sigma_px}}},
      {"window_bias", f.correct_window_bias ? nlohmann::json{{"min_model_fraction", f.window_bias.min_model_fraction},
                                                             {"max_bias_px", f.window_bias.max_bias_px}}
                                            : nlohmann::json(false)},
      {"widen_search", f.widen_disparity_search}};
}

}  // namespace

nlohmann::json OptionsJson(const AnalysisRunOptions& o) {
  const FrameAnalysisOptions& f = o.frame;
  const ReferenceModelOptions& r = o.reference.options;
  nlohmann::json options = {
      {"preset", ToString(o.preset)},
      {"disparity", DisparityJson(f)},
      {"reprojection",
       {{"max_depth_m", f.reprojection.max_depth_m},
        {"max_depth_over_median", f.reprojection.max_depth_over_median},
        {"keep_one_in", f.reprojection.keep_one_in},
        {"target_points", f.reprojection.target_points},
        {"disparity_offset_px", f.reprojection.disparity_offset_px}}},
      {"icp", RegistrationJson(f)},
      {"filter", {{"model", "constant velocity, causal (pose_filter.h)"}, {"window_s", o.filter.window_s}}},
      {"reference",
       {{"model", o.reference.model},
        {"num_points", r.num_points},
        {"seed", r.seed},
        {"shell",
         {{"cameras", ToString(r.cameras)},
          {"depth_tolerance_m", r.depth_tolerance_m},
          {"plane_depth_test", r.plane_depth_test},
          {"window_radius_px", r.neighbourhood_radius_px},
          {"raster_scale", r.raster_scale},
          {"min_incidence_deg", r.min_incidence_deg}}}}}};
  // Absent without --mask-boom, so the runs made before it keep their run.json.
  if (f.mask_boom)
    options["boom_mask"] = {{"margin_px", f.boom_mask.margin_px}, {"source", "sidecar boom angles, rig"}};
  // Diagnosis runs say so (absent otherwise).
  if (f.register_truth_cloud) {
    options["truth_cloud"] = {{"disparity_noise_px", f.truth_cloud_noise_px},
                              {"noise_seed", "splitmix64 of the frame index, Box-Muller"}};
  }
  // Absent without --mask-propellers, likewise.
  if (f.mask_propellers) {
    options["propeller_mask"] = {{"radial_margin_m", f.propeller_mask.radial_margin_m},
                                 {"axial_half_width_m", f.propeller_mask.axial_half_width_m},
                                 {"first_axial_half_width_m", f.propeller_mask.first_axial_half_width_m},
                                 {"passes", f.propeller_mask.passes},
                                 {"source", "common/include/aar/propeller.h's discs under the registered pose"}};
  }
  // Absent without --direct-stereo, likewise.
  if (f.refine_direct) {
    const DirectStereoOptions& d = f.direct;
    options["direct_stereo"] = {{"fit", ToString(d.fit)},
                                {"iterations", d.iterations},
                                {"edge_margin_px", d.edge_margin_px},
                                {"max_step_px", d.max_step_px},
                                {"min_cos_incidence", d.min_cos_incidence},
                                {"huber_k", d.huber_k},
                                {"converged_m", d.converged_m},
                                {"max_motion_px", d.max_motion_px}};
  }
  return options;
}

std::string DescribeSelection(const FrameSelection& s) {
  std::string text =
      std::to_string(s.begin) + ":" + (s.end == static_cast<size_t>(-1) ? std::string() : std::to_string(s.end));
  if (s.shard_count > 1) text += " shard " + std::to_string(s.shard_index) + "/" + std::to_string(s.shard_count);
  return text;
}

nlohmann::json BopJson(const BopObject& object, const Camera& left) {
  const Eigen::Matrix4d camera_from_tanker = left.tanker_from_camera.inverse().matrix();
  nlohmann::json matrix = nlohmann::json::array();
  for (int i = 0; i < 4; ++i)
    for (int k = 0; k < 4; ++k) matrix.push_back(camera_from_tanker(i, k));
  return {{"object", "the receiver mesh's distinct vertices"},
          {"vertices", object.vertices().size()},
          {"diameter_m", object.diameter_m()},
          {"image_width_px", left.intrinsics.width_px},
          {"camera_from_tanker", matrix}};
}

BopScale BopScaleOf(const nlohmann::json& run) {
  const nlohmann::json& bop = run.at("bop");
  return {bop.at("diameter_m").get<double>(), bop.at("image_width_px").get<int>()};
}

Eigen::Isometry3d CameraFromTanker(const nlohmann::json& run) {
  const nlohmann::json& matrix = run.at("bop").at("camera_from_tanker");
  Eigen::Matrix4d m;
  for (int i = 0; i < 4; ++i)
    for (int k = 0; k < 4; ++k) m(i, k) = matrix.at(static_cast<size_t>(4 * i + k)).get<double>();
  return Eigen::Isometry3d(m);
}

nlohmann::json ReadRunJson(const std::filesystem::path& dir) {
  const std::filesystem::path path = dir / kRunJsonName;
  if (!std::filesystem::is_regular_file(path)) {
    throw Error(path.string() + ": missing (the run did not finish, or this is not a run folder)");
  }
  nlohmann::json run = ReadJsonFile(path);
  for (const char* key :
       {"schema", "dataset_manifest_sha256", "model", "calibration", "options", "frames_analyzed", "bop"}) {
    if (!run.is_object() || !run.contains(key)) throw Error(path.string() + ": incomplete run.json (no '" + key + "')");
  }
  if (run.at("schema") != "aar-run/1") throw Error(path.string() + ": schema is not aar-run/1");
  if (!run.at("model").is_string() || !run.at("dataset_manifest_sha256").is_string() ||
      !run.at("frames_analyzed").is_number_unsigned()) {
    throw Error(path.string() + ": malformed run.json (model, dataset_manifest_sha256 or frames_analyzed)");
  }
  const nlohmann::json& bop = run.at("bop");
  const bool bop_ok = bop.is_object() && bop.contains("diameter_m") && bop.at("diameter_m").is_number() &&
                      bop.at("diameter_m").get<double>() > 0.0 && bop.contains("image_width_px") &&
                      bop.at("image_width_px").is_number_unsigned() && bop.at("image_width_px").get<int>() > 0 &&
                      bop.contains("camera_from_tanker") && bop.at("camera_from_tanker").is_array() &&
                      bop.at("camera_from_tanker").size() == 16 &&
                      std::all_of(bop.at("camera_from_tanker").begin(), bop.at("camera_from_tanker").end(),
                                  [](const nlohmann::json& v) { return v.is_number(); });
  if (!bop_ok) {
    throw Error(path.string() +
                ": malformed run.json ('bop' needs diameter_m > 0, image_width_px > 0 and a 16-number "
                "camera_from_tanker)");
  }
  return run;
}

}  // namespace aar
