#include "aar/analyzer/options_record.h"

#include <cmath>
#include <limits>

#include "aar/dataset.h"
#include "aar/error.h"

namespace aar {
namespace {

nlohmann::json Finite(double value) { return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json("inf"); }

nlohmann::json RegistrationJson(const FrameAnalysisOptions& f) {
  nlohmann::json registration = {
      {"algorithm", ToString(f.registration)}, {"seed", ToString(f.seed)},
      {"track_region", f.track_region},        {"track_margin_fraction", f.track_margin_fraction},
      {"track_margin_px", f.track_margin_px},  {"min_inlier_fraction", f.min_inlier_fraction}};
  if (f.seed == IcpSeed::kPreviousFrame) registration["max_seed_attitude_deg"] = f.max_seed_attitude_deg;
  if (f.registration == Registration::kPointToPoint) {
    const IcpOptions& i = f.icp;
    registration.update({{"max_iterations", i.max_iterations},
                         {"correspondence", ToString(i.correspondence)},
                         {"max_correspondence_distance_m", Finite(i.max_correspondence_distance_m)},
                         {"relative_mse_tolerance", i.relative_mse_tolerance},
                         {"translation_tolerance_m", i.translation_tolerance_m},
                         {"rotation_tolerance_rad", i.rotation_tolerance_rad},
                         {"kdtree_leaf_size", i.kdtree_leaf_size},
                         {"cache_nearest", i.cache_nearest}});
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
                         {"surface_noise_m", p.surface_noise_m},
                         {"translation_tolerance_m", p.translation_tolerance_m},
                         {"rotation_tolerance_rad", p.rotation_tolerance_rad},
                         {"balance_directions", p.balance_directions},
                         {"coarse_stride", p.coarse_stride},
                         {"coarse_min_points", p.coarse_min_points},
                         {"kdtree_leaf_size", p.kdtree_leaf_size}});
  }
  return registration;
}

nlohmann::json DisparityJson(const FrameAnalysisOptions& f) {
  const SubpixelOptions& s = f.subpixel;
  nlohmann::json json = {
      {"algorithm", f.disparity.algorithm == DisparityAlgorithm::kBlockMatching ? "bm" : "sgbm"},
      {"min_disparity", f.disparity.min_disparity},
      {"num_disparities", f.disparity.num_disparities},
      {"block_size", f.disparity.block_size},
      {"pre_filter_cap", f.disparity.pre_filter_cap},
      {"texture_threshold", f.disparity.texture_threshold},
      {"uniqueness_ratio", f.disparity.uniqueness_ratio},
      {"speckle_window_size", f.disparity.speckle_window_size},
      {"speckle_range_px", f.disparity.speckle_range_px},
      {"background_disparity_px", f.disparity.background_disparity_px},
      {"halo_radius_px", f.remove_halo ? f.halo.radius_px : 0},
      {"halo_max_jump_px", f.halo.max_jump_px},
      {"rounding_bias_px", f.remove_rounding_bias ? MatcherRoundingBiasPx(f.disparity.algorithm) : 0.0},
      {"subpixel", f.refine_subpixel ? (s.slanted ? "slanted" : "symmetric") : "none"},
      {"subpixel_window",
       {{"half_window_px", s.half_window_px},
        {"max_iterations", s.max_iterations},
        {"tolerance_px", s.tolerance_px},
        {"max_correction_px", s.max_correction_px},
        {"min_gradient_energy", s.min_gradient_energy},
        {"max_slope", s.max_slope}}},
      {"subpixel_interpolation",
       s.interpolation == SubpixelInterpolation::kLinear
           ? nlohmann::json(ToString(s.interpolation))
           : nlohmann::json{{"kind", ToString(s.interpolation)}, {"prefilter_sigma_px", s.prefilter_sigma_px}}},
      {"window_bias", f.correct_window_bias ? nlohmann::json{{"min_model_fraction", f.window_bias.min_model_fraction},
                                                             {"max_bias_px", f.window_bias.max_bias_px}}
                                            : nlohmann::json(false)},
      {"widen_search", f.widen_disparity_search}};
  // Absent when off (the default), so earlier records read back the same.
  if (f.remove_clipped) json["clipped"] = {{"level", f.clipped.clip_level}, {"radius_px", f.clipped.radius_px}};
  return json;
}

nlohmann::json ReferenceJson(const ReferenceRequest& reference) {
  const ReferenceModelOptions& r = reference.options;
  nlohmann::json json = {{"model", reference.model},
                         {"num_points", r.num_points},
                         {"seed", r.seed},
                         {"shell",
                          {{"cameras", ToString(r.cameras)},
                           {"depth_tolerance_m", r.depth_tolerance_m},
                           {"plane_depth_test", r.plane_depth_test},
                           {"window_radius_px", r.neighbourhood_radius_px},
                           {"raster_scale", r.raster_scale},
                           {"raster_size_px", {r.raster_width_px, r.raster_height_px}},
                           {"min_incidence_deg", r.min_incidence_deg}}}};
  // Absent for the rig's contact position (the default).
  if (r.tanker_from_receiver) json["shell"]["tanker_from_receiver"] = PoseToJson(*r.tanker_from_receiver);
  return json;
}

// Reads the keys of one object of the record; errors name the key's path.
class Record {
 public:
  Record(const nlohmann::json& json, std::string path, const std::string& where)
      : json_(json), path_(std::move(path)), where_(where) {}

  bool Has(const char* key) const { return json_.is_object() && json_.contains(key); }
  const nlohmann::json& At(const char* key) const {
    if (!Has(key)) throw Bad(key, "missing");
    return json_.at(key);
  }
  Record Object(const char* key) const {
    if (!At(key).is_object()) throw Bad(key, "not an object");
    return Record(At(key), path_ + key + ".", where_);
  }
  template <typename T>
  T Get(const char* key) const {
    try {
      return At(key).get<T>();
    } catch (const nlohmann::json::exception&) {
      throw Bad(key, "malformed");
    }
  }
  // A number, or "inf" for infinity (Finite).
  double FiniteOrInf(const char* key) const {
    if (At(key) == "inf") return std::numeric_limits<double>::infinity();
    return Get<double>(key);
  }
  // An enumeration through its parser (which throws aar::Error on unknown text).
  template <typename Parse>
  auto Parsed(const char* key, Parse parse) const {
    try {
      return parse(Get<std::string>(key));
    } catch (const Error& e) {
      throw Bad(key, e.what());
    }
  }
  Error Bad(const char* key, const std::string& why) const {
    return Error(where_ + ": options." + path_ + key + ": " + why);
  }

 private:
  const nlohmann::json& json_;
  std::string path_;
  const std::string& where_;
};

void ReadDisparity(const Record& d, FrameAnalysisOptions& f) {
  const std::string algorithm = d.Get<std::string>("algorithm");
  if (algorithm != "bm" && algorithm != "sgbm") throw d.Bad("algorithm", "expected bm or sgbm");
  f.disparity.algorithm = algorithm == "bm" ? DisparityAlgorithm::kBlockMatching : DisparityAlgorithm::kSemiGlobal;
  f.disparity.min_disparity = d.Get<int>("min_disparity");
  f.disparity.num_disparities = d.Get<int>("num_disparities");
  f.disparity.block_size = d.Get<int>("block_size");
  f.disparity.pre_filter_cap = d.Get<int>("pre_filter_cap");
  f.disparity.texture_threshold = d.Get<int>("texture_threshold");
  f.disparity.uniqueness_ratio = d.Get<int>("uniqueness_ratio");
  f.disparity.speckle_window_size = d.Get<int>("speckle_window_size");
  f.disparity.speckle_range_px = d.Get<double>("speckle_range_px");
  f.disparity.background_disparity_px = d.Get<double>("background_disparity_px");
  const int halo_radius_px = d.Get<int>("halo_radius_px");
  f.remove_halo = halo_radius_px > 0;
  if (f.remove_halo) f.halo.radius_px = halo_radius_px;
  f.halo.max_jump_px = d.Get<double>("halo_max_jump_px");
  f.remove_clipped = d.Has("clipped");
  if (f.remove_clipped) {
    const Record c = d.Object("clipped");
    f.clipped.clip_level = c.Get<int>("level");
    f.clipped.radius_px = c.Get<int>("radius_px");
  }
  f.remove_rounding_bias = d.Get<double>("rounding_bias_px") != 0.0;
  const std::string subpixel = d.Get<std::string>("subpixel");
  if (subpixel != "none" && subpixel != "slanted" && subpixel != "symmetric") {
    throw d.Bad("subpixel", "expected none, slanted or symmetric");
  }
  f.refine_subpixel = subpixel != "none";
  SubpixelOptions& s = f.subpixel;
  if (f.refine_subpixel) s.slanted = subpixel == "slanted";
  const Record window = d.Object("subpixel_window");
  s.half_window_px = window.Get<int>("half_window_px");
  s.max_iterations = window.Get<int>("max_iterations");
  s.tolerance_px = window.Get<double>("tolerance_px");
  s.max_correction_px = window.Get<double>("max_correction_px");
  s.min_gradient_energy = window.Get<double>("min_gradient_energy");
  s.max_slope = window.Get<double>("max_slope");
  if (d.At("subpixel_interpolation").is_string()) {
    s.interpolation = d.Parsed("subpixel_interpolation", ParseSubpixelInterpolation);
  } else {
    const Record interpolation = d.Object("subpixel_interpolation");
    s.interpolation = interpolation.Parsed("kind", ParseSubpixelInterpolation);
    s.prefilter_sigma_px = interpolation.Get<double>("prefilter_sigma_px");
  }
  f.correct_window_bias = !d.At("window_bias").is_boolean();
  if (!f.correct_window_bias && d.Get<bool>("window_bias")) throw d.Bad("window_bias", "true without its settings");
  if (f.correct_window_bias) {
    const Record w = d.Object("window_bias");
    f.window_bias.min_model_fraction = w.Get<double>("min_model_fraction");
    f.window_bias.max_bias_px = w.Get<double>("max_bias_px");
  }
  f.widen_disparity_search = d.Get<bool>("widen_search");
}

void ReadRegistration(const Record& r, FrameAnalysisOptions& f) {
  f.registration = r.Parsed("algorithm", ParseRegistration);
  f.seed = r.Parsed("seed", ParseIcpSeed);
  f.track_region = r.Get<bool>("track_region");
  f.track_margin_fraction = r.Get<double>("track_margin_fraction");
  f.track_margin_px = r.Get<int>("track_margin_px");
  f.min_inlier_fraction = r.Get<double>("min_inlier_fraction");
  if (f.seed == IcpSeed::kPreviousFrame) f.max_seed_attitude_deg = r.Get<double>("max_seed_attitude_deg");
  if (f.registration == Registration::kPointToPoint) {
    IcpOptions& i = f.icp;
    i.max_iterations = r.Get<int>("max_iterations");
    i.correspondence = r.Parsed("correspondence", ParseIcpCorrespondence);
    i.max_correspondence_distance_m = r.FiniteOrInf("max_correspondence_distance_m");
    i.relative_mse_tolerance = r.Get<double>("relative_mse_tolerance");
    i.translation_tolerance_m = r.Get<double>("translation_tolerance_m");
    i.rotation_tolerance_rad = r.Get<double>("rotation_tolerance_rad");
    i.kdtree_leaf_size = r.Get<int>("kdtree_leaf_size");
    i.cache_nearest = r.Get<bool>("cache_nearest");
    return;
  }
  PlaneIcpOptions& p = f.plane_icp;
  p.max_iterations = r.Get<int>("max_iterations");
  p.pairing = r.Parsed("pairing", ParsePlanePairing);
  p.residual = r.Parsed("residual", ParsePlaneResidual);
  p.converged_chi2 = r.Get<double>("converged_chi2");
  p.noise_bias_correction = r.Get<bool>("noise_bias_correction");
  const std::string surface = r.Get<std::string>("sensed_pairing_surface");
  if (surface != "full" && surface != "model") throw r.Bad("sensed_pairing_surface", "expected full or model");
  f.pair_sensed_with_full_surface = surface == "full";
  p.model_pull_scale_m = r.Get<double>("model_pull_scale_m");
  p.gate_sigmas = r.Get<double>("gate_sigmas");
  p.max_model_queries = r.Get<size_t>("max_model_queries");
  p.max_correspondence_distance_m = r.FiniteOrInf("max_correspondence_distance_m");
  p.robust_scale = r.Get<double>("robust_scale");
  p.disparity_noise_px = r.Get<double>("disparity_noise_px");
  p.lateral_noise_px = r.Get<double>("lateral_noise_px");
  p.surface_noise_m = r.Get<double>("surface_noise_m");
  p.translation_tolerance_m = r.Get<double>("translation_tolerance_m");
  p.rotation_tolerance_rad = r.Get<double>("rotation_tolerance_rad");
  p.balance_directions = r.Get<bool>("balance_directions");
  p.coarse_stride = r.Get<size_t>("coarse_stride");
  p.coarse_min_points = r.Get<size_t>("coarse_min_points");
  p.kdtree_leaf_size = r.Get<int>("kdtree_leaf_size");
}

void ReadReference(const Record& r, ReferenceRequest& reference) {
  reference.model = r.Get<std::string>("model");
  ReferenceModelOptions& o = reference.options;
  o.num_points = r.Get<size_t>("num_points");
  o.seed = r.Get<uint64_t>("seed");
  const Record shell = r.Object("shell");
  o.cameras = shell.Parsed("cameras", ParseShellCameras);
  o.depth_tolerance_m = shell.Get<double>("depth_tolerance_m");
  o.plane_depth_test = shell.Get<bool>("plane_depth_test");
  o.neighbourhood_radius_px = shell.Get<int>("window_radius_px");
  o.raster_scale = shell.Get<int>("raster_scale");
  const std::vector<int> size = shell.Get<std::vector<int>>("raster_size_px");
  if (size.size() != 2) throw shell.Bad("raster_size_px", "expected [width, height]");
  o.raster_width_px = size[0];
  o.raster_height_px = size[1];
  o.min_incidence_deg = shell.Get<double>("min_incidence_deg");
  o.tanker_from_receiver.reset();
  if (shell.Has("tanker_from_receiver")) {
    try {
      o.tanker_from_receiver = PoseFromJson(shell.At("tanker_from_receiver"), "");
    } catch (const std::exception& e) {
      throw shell.Bad("tanker_from_receiver", e.what());
    }
  }
}

// The optional stages: each present in the record exactly when it was on.
void ReadOptionalStages(const Record& o, AnalysisRunOptions& options) {
  FrameAnalysisOptions& f = options.frame;
  options.mask_boom = f.mask_boom = o.Has("boom_mask");
  if (f.mask_boom) {
    const Record b = o.Object("boom_mask");
    f.boom_mask.margin_px = b.Get<int>("margin_px");
    f.boom_mask.near_m = b.Get<double>("near_m");
  }
  f.register_truth_cloud = o.Has("truth_cloud");
  if (f.register_truth_cloud) f.truth_cloud_noise_px = o.Object("truth_cloud").Get<double>("disparity_noise_px");
  options.mask_propellers = f.mask_propellers = o.Has("propeller_mask");
  if (f.mask_propellers) {
    const Record m = o.Object("propeller_mask");
    f.propeller_mask.radial_margin_m = m.Get<double>("radial_margin_m");
    f.propeller_mask.axial_half_width_m = m.Get<double>("axial_half_width_m");
    f.propeller_mask.first_axial_half_width_m = m.Get<double>("first_axial_half_width_m");
    f.propeller_mask.passes = m.Get<int>("passes");
  }
  f.refine_direct = o.Has("direct_stereo");
  if (f.refine_direct) {
    const Record d = o.Object("direct_stereo");
    DirectStereoOptions& s = f.direct;
    s.fit = d.Parsed("fit", ParseDirectStereoFit);
    s.iterations = d.Get<int>("iterations");
    s.edge_margin_px = d.Get<int>("edge_margin_px");
    s.max_step_px = d.Get<double>("max_step_px");
    s.min_cos_incidence = d.Get<double>("min_cos_incidence");
    s.huber_k = d.Get<double>("huber_k");
    s.converged_m = d.Get<double>("converged_m");
    s.max_motion_px = d.Get<double>("max_motion_px");
  }
}

}  // namespace

nlohmann::json OptionsJson(const AnalysisRunOptions& o) {
  const FrameAnalysisOptions& f = o.frame;
  nlohmann::json options = {
      {"preset", ToString(o.preset)},
      {"disparity", DisparityJson(f)},
      {"reprojection",
       {{"min_depth_m", f.reprojection.min_depth_m},
        {"max_depth_m", f.reprojection.max_depth_m},
        {"max_depth_over_median", f.reprojection.max_depth_over_median},
        {"keep_one_in", f.reprojection.keep_one_in},
        {"target_points", f.reprojection.target_points},
        {"disparity_offset_px", f.reprojection.disparity_offset_px}}},
      {"icp", RegistrationJson(f)},
      {"acceptance",
       {{"min_sensed_points", f.min_sensed_points},
        {"max_residual_m", f.max_icp_rmse_m},
        {"disparity_noise_px", f.disparity_noise_px}}},
      {"filter", {{"model", "constant velocity, causal (pose_filter.h)"}, {"window_s", o.filter.window_s}}},
      {"reference", ReferenceJson(o.reference)}};
  // The optional stages: absent when off, so the runs made before they existed keep their run.json.
  if (f.mask_boom) {
    options["boom_mask"] = {
        {"margin_px", f.boom_mask.margin_px}, {"near_m", f.boom_mask.near_m}, {"source", "sidecar boom angles, rig"}};
  }
  if (f.register_truth_cloud) {  // diagnosis runs say so
    options["truth_cloud"] = {{"disparity_noise_px", f.truth_cloud_noise_px},
                              {"noise_seed", "splitmix64 of the frame index, Box-Muller"}};
  }
  if (f.mask_propellers) {
    options["propeller_mask"] = {{"radial_margin_m", f.propeller_mask.radial_margin_m},
                                 {"axial_half_width_m", f.propeller_mask.axial_half_width_m},
                                 {"first_axial_half_width_m", f.propeller_mask.first_axial_half_width_m},
                                 {"passes", f.propeller_mask.passes},
                                 {"source", "common/include/aar/propeller.h's discs under the registered pose"}};
  }
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

void ApplyRecordedOptions(const nlohmann::json& recorded, const std::string& where, AnalysisRunOptions& options) {
  const Record o(recorded, "", where);
  if (!recorded.is_object()) throw Error(where + ": options: not an object");
  options.preset = o.Parsed("preset", ParsePreset);
  FrameAnalysisOptions& f = options.frame;
  f = FrameAnalysisOptions::ForPreset(options.preset);
  ReadDisparity(o.Object("disparity"), f);
  const Record r = o.Object("reprojection");
  f.reprojection.min_depth_m = r.Get<double>("min_depth_m");
  f.reprojection.max_depth_m = r.Get<double>("max_depth_m");
  f.reprojection.max_depth_over_median = r.Get<double>("max_depth_over_median");
  f.reprojection.keep_one_in = r.Get<size_t>("keep_one_in");
  f.reprojection.target_points = r.Get<size_t>("target_points");
  f.reprojection.disparity_offset_px = r.Get<double>("disparity_offset_px");
  ReadRegistration(o.Object("icp"), f);
  const Record acceptance = o.Object("acceptance");
  f.min_sensed_points = acceptance.Get<size_t>("min_sensed_points");
  f.max_icp_rmse_m = acceptance.Get<double>("max_residual_m");
  f.disparity_noise_px = acceptance.Get<double>("disparity_noise_px");
  options.filter.window_s = o.Object("filter").Get<double>("window_s");
  ReadReference(o.Object("reference"), options.reference);
  ReadOptionalStages(o, options);
  try {
    f.Check();
    options.reference.options.Check();
  } catch (const Error& e) {
    throw Error(where + ": options: " + e.what());
  }
}

}  // namespace aar
