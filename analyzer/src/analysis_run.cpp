#include "aar/analyzer/analysis_run.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <set>
#include <utility>

#include "aar/analyzer/bop_metrics.h"
#include "aar/analyzer/mesh.h"
#include "aar/analyzer/ply.h"
#include "aar/analyzer/stereo_truth.h"
#include "aar/error.h"
#include "aar/file_io.h"
#include "aar/flight_path.h"
#include "aar/folder_lock.h"
#include "aar/output_folder.h"
#include "aar/progress.h"
#include "aar/region.h"

namespace aar {
namespace {

nlohmann::json MatJson(const cv::Mat& m) {
  nlohmann::json rows = nlohmann::json::array();
  for (int r = 0; r < m.rows; ++r) {
    nlohmann::json row = nlohmann::json::array();
    for (int c = 0; c < m.cols; ++c) row.push_back(m.at<double>(r, c));
    rows.push_back(row);
  }
  return rows;
}

nlohmann::json Finite(double value) { return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json("inf"); }

nlohmann::json OptionsJson(const AnalysisRunOptions& o) {
  const FrameAnalysisOptions& f = o.frame;
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
  const ReferenceModelOptions& r = o.reference.options;
  nlohmann::json options = {
      {"preset", ToString(o.preset)},
      {"disparity",
       {{"algorithm", f.disparity.algorithm == DisparityAlgorithm::kBlockMatching ? "bm" : "sgbm"},
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
        {"widen_search", f.widen_disparity_search}}},
      {"reprojection",
       {{"max_depth_m", f.reprojection.max_depth_m},
        {"max_depth_over_median", f.reprojection.max_depth_over_median},
        {"keep_one_in", f.reprojection.keep_one_in},
        {"target_points", f.reprojection.target_points},
        {"disparity_offset_px", f.reprojection.disparity_offset_px}}},
      {"icp", registration},
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
  return options;
}

std::string DescribeSelection(const FrameSelection& s) {
  std::string text =
      std::to_string(s.begin) + ":" + (s.end == static_cast<size_t>(-1) ? std::string() : std::to_string(s.end));
  if (s.shard_count > 1) text += " shard " + std::to_string(s.shard_index) + "/" + std::to_string(s.shard_count);
  return text;
}

// run.json's "bop": what the BOP scores and results file need (bop_metrics.h).
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

void WriteSummary(const std::filesystem::path& out, const nlohmann::json& run, const ModelSummary& summary,
                  const std::vector<FrameResult>& frames) {
  // From the estimates as frames.csv stores them, so that a merge of shards writes the same file.
  WriteFileAtomic(out / kBopResultsName, FormatBopResults(ParseFrameResults(FormatFrameResults(frames), kFramesCsvName),
                                                          CameraFromTanker(run)));
  Summary all;
  all.models.push_back(summary);
  nlohmann::json json = SummaryToJson(all);
  json["run"] = {{"dataset_manifest_sha256", run.at("dataset_manifest_sha256")},
                 {"calibration", run.at("calibration")},
                 {"options", run.at("options")}};
  WriteJsonFile(out / kSummaryJsonName, json);
  const std::string markdown = "# Pose estimation summary\n\nModel: " + summary.model +
                               ". Dataset manifest SHA-256: " + run.at("dataset_manifest_sha256").get<std::string>() +
                               ".\n\n" + SummaryToMarkdown(all);
  WriteFileAtomic(out / kSummaryMarkdownName, markdown);
}

// The dataset's copies of the render inputs must be the files the manifest
// recorded (inputs.*.sha256 and files), or the analysis would silently use
// another rig, flight path or receiver model than the images were made with.
void CheckDatasetInputs(const std::filesystem::path& dataset, const Manifest& manifest, bool uses_receiver) {
  const std::pair<const char*, const char*> inputs[] = {{"rig", kRigName},
                                                        {"flight_path", kFlightPathName},
                                                        {"receiver_model", kReceiverModelName},
                                                        {"boom_model", kBoomModelName},
                                                        {"boom_tube_model", kBoomTubeModelName}};
  const nlohmann::json recorded = manifest.json.value("inputs", nlohmann::json::object());
  for (const auto& [key, name] : inputs) {
    std::vector<std::string> hashes;
    if (const auto it = manifest.files.find(name); it != manifest.files.end()) hashes.push_back(it->second);
    if (recorded.is_object() && recorded.contains(key) && recorded.at(key).is_object() &&
        recorded.at(key).value("file", "") == name && recorded.at(key).contains("sha256")) {
      if (!recorded.at(key).at("sha256").is_string()) {
        throw Error((dataset / kManifestName).string() + ": inputs." + key + ".sha256 is not a string");
      }
      hashes.push_back(recorded.at(key).at("sha256").get<std::string>());
    }
    const std::filesystem::path file = dataset / name;
    if (hashes.empty()) continue;
    if (!std::filesystem::is_regular_file(file)) {
      if (std::string(name) == kFlightPathName || (std::string(name) == kReceiverModelName && !uses_receiver)) continue;
      throw Error(file.string() + ": missing (manifest.json records it)");
    }
    const std::string actual = Sha256File(file);
    for (const std::string& hash : hashes) {
      if (hash != actual) {
        throw Error(file.string() +
                    ": SHA-256 differs from manifest.json's (changed after rendering; restore it or "
                    "render again)");
      }
    }
  }
}

// A shard's run.json: present (the run finished) and with the keys merge compares.
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

}  // namespace

ReferenceModel BuildReferenceModel(const TriangleMesh& mesh, const StereoRig& rig, const ReferenceRequest& request,
                                   ReferenceModel* full_out) {
  request.options.Check();
  if (request.model != "full" && request.model != "shelled") {
    throw Error("--model '" + request.model + "': expected full or shelled");
  }
  ReferenceModel full = FullModel(mesh, request.options);
  ReferenceModel model = request.model == "full" ? full : ShellModel(full, mesh, rig, request.options);
  if (full_out != nullptr) *full_out = std::move(full);
  return model;
}

CalibrateOutput CalibrateDataset(const std::filesystem::path& dataset, const CalibrationOptions& options) {
  CalibrateOutput out;
  out.result = CalibrateFromDataset(dataset, options);
  const CalibrationResult& r = out.result;
  nlohmann::json pairs = nlohmann::json::array();
  for (const PairDetection& p : r.pairs) pairs.push_back({{"used", p.used}, {"reason", p.reason}});
  out.report = {{"schema", "aar-calibration-report/1"},
                {"rms_reprojection_px", r.rms_reprojection_px},
                {"left_rms_px", r.left_rms_px},
                {"right_rms_px", r.right_rms_px},
                {"epipolar_error_px", r.epipolar_error_px},
                {"epipolar_algebraic", r.epipolar_algebraic},
                {"corner_count", r.corner_count},
                {"used_pairs", r.used_pairs},
                {"board_depth_m", {r.board_depth_min_m, r.board_depth_max_m}},
                {"same_focal_length", options.same_focal_length},
                {"pairs", pairs},
                {"Q", MatJson(r.calibration.Q)}};
  if (r.distortion_estimated) {
    out.report["distortion"] = {
        {"model", DistortionModelName(options.distortion == DistortionModel::kAuto ? DistortionModel::kBrownConrady
                                                                                   : options.distortion)},
        {"D1", MatJson(r.calibration.D1)},
        {"D2", MatJson(r.calibration.D2)}};
  }
  if (r.versus_ideal) {
    const IdealComparison& v = *r.versus_ideal;
    out.report["versus_ideal"] = {{"q_percent_error", MatJson(v.q_percent_error)},
                                  {"focal_error_percent", v.focal_error_percent},
                                  {"baseline_error_percent", v.baseline_error_percent},
                                  {"left_fx_error_percent", v.left_fx_error_percent},
                                  {"right_fx_error_percent", v.right_fx_error_percent},
                                  {"left_principal_point_error_px", v.left_principal_point_error_px},
                                  {"rotation_error_deg", v.rotation_error_deg},
                                  {"baseline_direction_error_deg", v.baseline_direction_error_deg}};
    if (r.distortion_estimated) {
      out.report["versus_ideal"]["D1_error"] = v.left_distortion_error;
      out.report["versus_ideal"]["D2_error"] = v.right_distortion_error;
    }
    out.report["versus_ideal"]["left_ray_error_max_px"] = v.left_ray_error_max_px;
    out.report["versus_ideal"]["right_ray_error_max_px"] = v.right_ray_error_max_px;
  }
  return out;
}

void WriteCalibrationOutputs(const std::filesystem::path& out, const CalibrateOutput& calibration) {
  EnsureWritableDirectory(out);
  WriteCalibration(out / kCalibrationYamlName, calibration.result.calibration);
  WriteJsonFile(out / kCalibrationReportName, calibration.report);
}

namespace {

// The manifest lists the boom's two models (a dataset rendered with the boom).
bool HasBoom(const Manifest& manifest) {
  const nlohmann::json inputs = manifest.json.value("inputs", nlohmann::json::object());
  return inputs.is_object() && inputs.contains("boom_model") && inputs.contains("boom_tube_model");
}

// The manifest's propellers turn (a dataset rendered with --propellers).
bool PropellersTurn(const Manifest& manifest) {
  const nlohmann::json frames = manifest.json.value("frames", nlohmann::json::object());
  return frames.is_object() && frames.contains("propellers") && frames["propellers"].value("rpm", 0.0) > 0.0;
}

// The options with the masks decided: as asked, or, when not asked, on with the default preset for what the
// dataset has.
AnalysisRunOptions WithMasks(const AnalysisRunOptions& requested, const Manifest& manifest) {
  AnalysisRunOptions options = requested;
  const bool defaults = options.preset == Preset::kDefault;
  options.frame.mask_boom = options.mask_boom.value_or(defaults && HasBoom(manifest));
  options.frame.mask_propellers = options.mask_propellers.value_or(defaults && PropellersTurn(manifest));
  return options;
}

}  // namespace

AnalysisRunResult RunAnalysis(const AnalysisRunOptions& requested) {
  // Everything that makes the run impossible fails here, before any output.
  requested.frame.Check();
  const Manifest manifest = ReadManifest(requested.dataset);
  const AnalysisRunOptions options = WithMasks(requested, manifest);
  if (options.write_outputs) CheckOutputFolder(options.out);
  const std::string manifest_path = (options.dataset / kManifestName).string();
  if (manifest.frame_count == 0) throw Error(manifest_path + ": dataset has no frames");
  // Options that could only leave every frame unmeasured or unchanged are refused here.
  if (options.frame.mask_propellers && !PropellersTurn(manifest)) {
    throw Error("--mask-propellers: " + manifest_path +
                " records no turning propellers (frames.propellers.rpm; render with --propellers)");
  }
  if (options.frame.register_truth_cloud && !manifest.json.at("frames").value("depth", false)) {
    throw Error("--truth-cloud: " + manifest_path + " records no depth truth (frames.depth; render with --depth)");
  }
  options.selection.CheckWithin(manifest.frame_count, manifest_path);
  CheckDatasetInputs(options.dataset, manifest, !options.receiver_model);
  // Truth for frames whose sidecar cannot be read comes from the flight path.
  std::vector<FlightSample> flight_path;
  if (std::filesystem::is_regular_file(options.dataset / kFlightPathName)) {
    flight_path = ReadFlightPath(options.dataset / kFlightPathName);
    if (flight_path.size() != manifest.frame_count) {
      throw Error(manifest_path + ": frames.count " + std::to_string(manifest.frame_count) + " differs from the " +
                  std::to_string(flight_path.size()) + " samples of " + (options.dataset / kFlightPathName).string());
    }
  }
  const std::vector<size_t> selected = options.selection.Select(manifest.frame_count);
  if (manifest.complete) {
    // A complete manifest lists every frame: one that is not there would go unchecked.
    for (size_t index : selected) {
      const std::string sidecar =
          std::filesystem::relative(SidecarPath(options.dataset, "frame", index), options.dataset).generic_string();
      if (!manifest.files.contains(sidecar)) {
        throw Error(manifest_path + ": complete, but 'files' does not list " + sidecar);
      }
    }
  }
  const StereoRig rig = LoadRig(options.dataset / kRigName);
  if (options.frame.disparity.num_disparities >= rig.left.intrinsics.width_px) {
    throw Error("--num-disparities " + std::to_string(options.frame.disparity.num_disparities) +
                ": must be below the image width (" + std::to_string(rig.left.intrinsics.width_px) + " px, " +
                (options.dataset / kRigName).string() + ")");
  }
  std::optional<CalibrateOutput> calibrated;
  StereoCalibration calibration;
  nlohmann::json calibration_source;
  if (options.calibration) {
    calibration = ReadCalibration(*options.calibration);
    calibration_source = {{"file", options.calibration->filename().string()},
                          {"sha256", Sha256File(*options.calibration)}};
  } else {
    calibrated = CalibrateDataset(options.dataset, options.calibration_options);
    calibration = calibrated->result.calibration;
    calibration_source = {{"calibrated_from", "calib/"}, {"used_pairs", calibrated->result.used_pairs}};
  }
  const cv::Size rig_size(rig.left.intrinsics.width_px, rig.left.intrinsics.height_px);
  if (calibration.image_size != rig_size) {
    throw Error((options.calibration ? options.calibration->string() : std::string("calibration")) + ": image size " +
                std::to_string(calibration.image_size.width) + "x" + std::to_string(calibration.image_size.height) +
                " differs from the dataset's " + std::to_string(rig_size.width) + "x" +
                std::to_string(rig_size.height));
  }
  const TriangleMesh mesh = LoadReceiverMesh(options.receiver_model.value_or(options.dataset / kReceiverModelName));
  ReferenceModel full_surface;  // for FrameAnalysisOptions::pair_sensed_with_full_surface
  const ReferenceModel reference = BuildReferenceModel(mesh, rig, options.reference, &full_surface);
  if (options.progress) {
    std::fprintf(stderr, "reference model '%s': %zu points\n", reference.name.c_str(),
                 reference.points_in_receiver.size());
  }
  const BopObject bop_object(mesh);
  const Eigen::Isometry3d left_from_tanker = rig.left.tanker_from_camera.inverse();
  FrameAnalyzer analyzer(calibration, rig.left.tanker_from_camera, reference, options.frame, &full_surface);
  if (options.frame.correct_window_bias) analyzer.EnableWindowBiasCorrection(mesh);
  if (options.frame.mask_boom) {
    // CheckDatasetInputs has checked the copies against the hashes the manifest records.
    if (!HasBoom(manifest)) {
      throw Error("--mask-boom: " + options.dataset.string() +
                  " has no boom (boom.glb, boom_tube.glb: render a flight path with the boom columns, or --boom)");
    }
    analyzer.EnableBoomMask(LoadReceiverMesh(options.dataset / kBoomModelName),
                            LoadReceiverMesh(options.dataset / kBoomTubeModelName));
  }

  for (size_t index : options.dump_frames) {
    if (!std::binary_search(selected.begin(), selected.end(), index)) {
      throw Error("--dump-frames " + std::to_string(index) + ": not among the frames analyzed (" +
                  std::to_string(selected.size()) + " selected of " + std::to_string(manifest.frame_count) + ")");
    }
  }
  const nlohmann::json run = {{"schema", "aar-run/1"},
                              {"dataset_manifest_sha256", Sha256File(options.dataset / kManifestName)},
                              {"model", reference.name},
                              {"reference_points", reference.points_in_receiver.size()},
                              {"calibration", calibration_source},
                              {"frames", DescribeSelection(options.selection)},
                              {"frames_analyzed", selected.size()},
                              {"options", OptionsJson(options)},
                              {"bop", BopJson(bop_object, rig.left)}};
  // Written into a staging folder and put in place at the end (output_folder.h).
  std::optional<StagedOutput> staged;
  std::filesystem::path out;
  if (options.write_outputs) {
    staged.emplace(options.out, "run");
    out = staged->path();
    if (calibrated) {
      WriteCalibrationOutputs(out, *calibrated);
    } else {
      WriteCalibration(out / kCalibrationYamlName, calibration);
    }
    WritePly(out / ("reference_" + reference.name + ".ply"), reference.points_in_receiver,
             {"aar-analyze reference model '" + reference.name + "', receiver frame, metres"});
  }

  AnalysisRunResult result;
  result.reference_points = reference.points_in_receiver.size();
  Progress progress("analyze " + reference.name, selected.size());
  TrackHistory history;
  const std::set<size_t> dump_frames(options.dump_frames.begin(), options.dump_frames.end());
  DumpProjection projection;
  if (!dump_frames.empty()) {
    cv::Mat m1;
    calibration.M1.convertTo(m1, CV_64F);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) projection.left_camera_matrix(i, j) = m1.at<double>(i, j);
    cv::Mat d1;
    calibration.D1.convertTo(d1, CV_64F);
    projection.left_distortion = {d1.at<double>(0, 0), d1.at<double>(0, 1), d1.at<double>(0, 2), d1.at<double>(0, 3),
                                  d1.at<double>(0, 4)};
    projection.left_from_tanker = rig.left.tanker_from_camera.inverse();
    projection.model_points_in_receiver = reference.points_in_receiver;
  }
  for (size_t index : selected) {
    FrameDump dump;
    const bool dumped = options.write_outputs && dump_frames.contains(index);
    std::optional<DepthTruth> depth;  // VSD's test depth, where the dataset has it
    FrameResult frame = analyzer.Analyze(options.dataset, index, manifest, history, dumped ? &dump : nullptr, &depth);
    if (dumped) WriteFrameDump(out / kFrameDumpDir, index, dump, projection);
    if (frame.ok()) {
      history.before_last = history.last;
      history.last = std::make_pair(frame.time_s, frame.estimate);
    } else {
      if (frame.range_m == 0.0 && index < flight_path.size()) {
        frame.time_s = flight_path[index].time_s;
        frame.truth = flight_path[index].tanker_from_receiver;
        frame.range_m = (frame.truth.translation_m - rig.left.tanker_from_camera.translation()).norm();
        frame.region = RegionForRange(frame.range_m);
      }
      history = TrackHistory{};
      if (options.progress) std::fprintf(stderr, "frame %zu not measured: %s\n", index, frame.status.c_str());
    }
    if (frame.has_estimate) {
      const Eigen::Isometry3d estimate = left_from_tanker * IsometryFromPose(frame.estimate);
      const Eigen::Isometry3d truth = left_from_tanker * IsometryFromPose(frame.truth);
      frame.bop_errors = ComputePoseErrorMetrics(bop_object, rig.left.intrinsics, estimate, truth);
      if (depth && rig.left.intrinsics.distortion.IsZero()) {  // BOP's camera is a pinhole
        frame.bop_errors->vsd =
            ComputeVsd(mesh, rig.left.intrinsics, estimate, truth, depth->depth_m, bop_object.diameter_m(), rig.near_m);
      }
    }
    result.frames.push_back(std::move(frame));
    if (options.progress) progress.Advance();
  }
  if (options.progress) progress.Finish();
  FilterFrameResults(result.frames, options.filter);
  result.summary = SummarizeFrames(reference.name, result.frames, BopScaleOf(run));
  if (options.write_outputs) {
    WriteFrameResults(out / kFramesCsvName, result.frames);
    WriteSummary(out, run, result.summary, result.frames);
    WriteJsonFile(out / kRunJsonName, run);
    staged->Commit();
  }
  return result;
}

void MergeRuns(const std::vector<std::filesystem::path>& shard_dirs, const std::filesystem::path& out) {
  if (shard_dirs.empty()) throw Error("merge: no shard folders given");
  CheckOutputFolder(out);
  std::error_code ec;
  const std::filesystem::path out_canonical = std::filesystem::weakly_canonical(out, ec);
  std::vector<FileLock> shard_locks;  // no run may be writing a shard while it is read
  std::vector<std::filesystem::path> seen;
  for (const std::filesystem::path& dir : shard_dirs) {
    const std::filesystem::path canonical = std::filesystem::weakly_canonical(dir, ec);
    if (std::find(seen.begin(), seen.end(), canonical) != seen.end()) {
      throw Error(dir.string() + ": shard folder given twice");
    }
    seen.push_back(canonical);
    const auto [in_shard, in_out] =
        std::mismatch(canonical.begin(), canonical.end(), out_canonical.begin(), out_canonical.end());
    if (in_shard == canonical.end()) {
      throw Error(out.string() + ": --out is one of the shard folders or inside one; merge into a new folder");
    }
    if (in_out == out_canonical.end()) {
      throw Error(out.string() + ": --out holds the shard folder " + dir.string() + "; merge into a new folder");
    }
    shard_locks.push_back(LockOutputFolder(dir));
  }
  std::vector<std::vector<FrameResult>> shards;
  std::vector<std::string> names;
  nlohmann::json first_run;
  size_t frames_analyzed = 0;
  for (const std::filesystem::path& dir : shard_dirs) {
    nlohmann::json run = ReadRunJson(dir);
    if (first_run.is_null()) {
      first_run = run;
    } else {
      for (const char* key : {"dataset_manifest_sha256", "model", "calibration", "options", "bop"}) {
        if (run.at(key) != first_run.at(key)) {
          throw Error((dir / kRunJsonName).string() + ": '" + key + "' differs from " +
                      (shard_dirs.front() / kRunJsonName).string());
        }
      }
    }
    shards.push_back(ReadFrameResults(dir / kFramesCsvName));
    names.push_back((dir / kFramesCsvName).string());
    const size_t analyzed = run.at("frames_analyzed").get<size_t>();
    if (shards.back().size() != analyzed) {
      throw Error(names.back() + ": " + std::to_string(shards.back().size()) + " frames, but run.json says " +
                  std::to_string(analyzed) + " were analyzed (frames.csv of another run?)");
    }
    frames_analyzed += analyzed;
  }
  std::vector<FrameResult> merged = MergeFrameResults(shards, names);
  PoseFilterOptions filter;
  const nlohmann::json& options = first_run.at("options");
  if (options.contains("filter")) filter.window_s = options.at("filter").at("window_s").get<double>();
  FilterFrameResults(merged, filter);
  StagedOutput staged(out, "merge");
  first_run["frames"] = "merged from " + std::to_string(shard_dirs.size()) + " shards";
  first_run["frames_analyzed"] = frames_analyzed;
  WriteFrameResults(staged.path() / kFramesCsvName, merged);
  WriteSummary(staged.path(), first_run,
               SummarizeFrames(first_run.at("model").get<std::string>(), merged, BopScaleOf(first_run)), merged);
  WriteJsonFile(staged.path() / kRunJsonName, first_run);
  staged.Commit();
}

}  // namespace aar
