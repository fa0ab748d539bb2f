#include "aar/analyzer/analysis_run.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <set>
#include <utility>

#include "aar/analyzer/bench_yardstick.h"
#include "aar/analyzer/bop_metrics.h"
#include "aar/analyzer/mesh.h"
#include "aar/analyzer/options_record.h"
#include "aar/analyzer/ply.h"
#include "aar/analyzer/run_record.h"
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

CalibrateOutput CalibrateDataset(const OpenedDataset& dataset, const CalibrationOptions& options) {
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

// What a run reads from the dataset before its first frame, checked: every
// problem that makes the run impossible fails here, before any output.
struct RunInputs {
  OpenedDataset dataset;
  AnalysisRunOptions options;  // the request with the dataset's masks
  std::vector<size_t> selected;
};

RunInputs OpenRunInputs(const AnalysisRunOptions& requested) {
  requested.frame.Check();
  RunInputs in{OpenedDataset::Open(requested.dataset), {}, {}};
  const Manifest& manifest = in.dataset.manifest();
  in.options = WithMasks(requested, manifest);
  const AnalysisRunOptions& options = in.options;
  if (options.write_outputs) CheckOutputFolder(options.out);
  const std::string manifest_path = in.dataset.PathOf(kManifestName);
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
  in.selected = options.selection.Select(manifest.frame_count);
  for (size_t index : in.selected) in.dataset.CheckListed("frame", index);  // before any output, not per frame
  const StereoRig& rig = in.dataset.rig();
  if (options.frame.disparity.num_disparities >= rig.left.intrinsics.width_px) {
    throw Error("--num-disparities " + std::to_string(options.frame.disparity.num_disparities) +
                ": must be below the image width (" + std::to_string(rig.left.intrinsics.width_px) + " px, " +
                in.dataset.PathOf(kRigName) + ")");
  }
  for (size_t index : options.dump_frames) {
    if (!std::binary_search(in.selected.begin(), in.selected.end(), index)) {
      throw Error("--dump-frames " + std::to_string(index) + ": not among the frames analyzed (" +
                  std::to_string(in.selected.size()) + " selected of " + std::to_string(manifest.frame_count) + ")");
    }
  }
  return in;
}

// The receiver's mesh: the file given, or the dataset's copy (checked against the manifest by Open).
TriangleMesh LoadRunReceiver(const RunInputs& in) {
  if (in.options.receiver_model) return LoadReceiverMesh(*in.options.receiver_model);
  return LoadInputMesh(in.dataset, kReceiverModelName);
}

// The run's calibration: the file given, or one from the dataset's boards.
struct RunCalibration {
  std::optional<CalibrateOutput> calibrated;  // when calibrated from calib/
  StereoCalibration calibration;
  nlohmann::json source;  // run.json's "calibration"
};

RunCalibration LoadRunCalibration(const AnalysisRunOptions& options, const OpenedDataset& dataset) {
  RunCalibration c;
  if (options.calibration) {
    CheckRegularFile(*options.calibration, "calibration file");
    const std::string yaml = ReadFileBytes(*options.calibration);
    c.calibration = ParseCalibration(yaml, options.calibration->string());
    c.source = {{"file", options.calibration->filename().string()}, {"sha256", Sha256Hex(yaml)}};
  } else {
    c.calibrated = CalibrateDataset(dataset, options.calibration_options);
    c.calibration = c.calibrated->result.calibration;
    c.source = {{"calibrated_from", "calib/"}, {"used_pairs", c.calibrated->result.used_pairs}};
  }
  const StereoRig& rig = dataset.rig();
  const cv::Size rig_size(rig.left.intrinsics.width_px, rig.left.intrinsics.height_px);
  if (c.calibration.image_size != rig_size) {
    throw Error((options.calibration ? options.calibration->string() : std::string("calibration")) + ": image size " +
                std::to_string(c.calibration.image_size.width) + "x" + std::to_string(c.calibration.image_size.height) +
                " differs from the dataset's " + std::to_string(rig_size.width) + "x" +
                std::to_string(rig_size.height));
  }
  return c;
}

// How the frame dumps draw the model over the left image.
DumpProjection DumpProjectionOf(const StereoCalibration& calibration, const StereoRig& rig,
                                const ReferenceModel& reference) {
  DumpProjection projection;
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
  return projection;
}

// The BOP errors of a frame with an estimate (bop_metrics.h), in the left
// camera, with VSD where the frame has depth truth and the rig is a pinhole
// (BOP's camera).
void ScoreFrame(FrameResult& frame, const std::optional<DepthTruth>& depth, const BopObject& object,
                const TriangleMesh& mesh, const StereoRig& rig) {
  if (!frame.has_estimate) return;
  const Eigen::Isometry3d left_from_tanker = rig.left.tanker_from_camera.inverse();
  const Eigen::Isometry3d estimate = left_from_tanker * IsometryFromPose(frame.estimate);
  const Eigen::Isometry3d truth = left_from_tanker * IsometryFromPose(frame.truth);
  frame.bop_errors = ComputePoseErrorMetrics(object, rig.left.intrinsics, estimate, truth);
  if (depth && rig.left.intrinsics.distortion.IsZero()) {
    frame.bop_errors->vsd =
        ComputeVsd(mesh, rig.left.intrinsics, estimate, truth, depth->depth_m, object.diameter_m(), rig.near_m);
  }
}

// The receiver mesh for the model passes, and the boom mask, where the options ask for them.
void EnableCorrections(FrameAnalyzer& analyzer, const RunInputs& in, const TriangleMesh& mesh) {
  const AnalysisRunOptions& options = in.options;
  if (options.frame.correct_window_bias || options.frame.refine_direct) analyzer.SetReceiverMesh(mesh);
  if (options.frame.mask_boom) {
    // OpenedDataset::Open has checked the copies against the hashes the manifest records.
    if (!HasBoom(in.dataset.manifest())) {
      throw Error("--mask-boom: " + options.dataset.string() +
                  " has no boom (boom.glb, boom_tube.glb: render a flight path with the boom columns, or --boom)");
    }
    analyzer.EnableBoomMask(LoadInputMesh(in.dataset, kBoomModelName), LoadInputMesh(in.dataset, kBoomTubeModelName));
  }
}

// The run's record (run.json).
nlohmann::json RunRecord(const RunInputs& in, const RunCalibration& calibration, const ReferenceModel& reference,
                         const BopObject& bop_object) {
  const AnalysisRunOptions& options = in.options;
  return {{"schema", "aar-run/1"},
          {"dataset_manifest_sha256", in.dataset.manifest_sha256()},
          {"model", reference.name},
          {"reference_points", reference.points_in_receiver.size()},
          {"calibration", calibration.source},
          {"frames", DescribeSelection(options.selection)},
          {"frames_analyzed", in.selected.size()},
          {"options", OptionsJson(options)},
          {"bop", BopJson(bop_object, in.dataset.rig().left)}};
}

// The run's calibration and reference model, into its output folder `out`.
void WriteRunInputs(const std::filesystem::path& out, const RunCalibration& calibration,
                    const ReferenceModel& reference) {
  if (calibration.calibrated) {
    WriteCalibrationOutputs(out, *calibration.calibrated);
  } else {
    WriteCalibration(out / kCalibrationYamlName, calibration.calibration);
  }
  WritePly(out / ("reference_" + reference.name + ".ply"), reference.points_in_receiver,
           {"aar-analyze reference model '" + reference.name + "', receiver frame, metres"});
}

// A frame the analysis stopped on before reading its sidecar: its time,
// truth, range and region from the flight path.
void FillFromFlightPath(FrameResult& frame, const OpenedDataset& dataset, size_t index) {
  const std::vector<FlightSample>& path = dataset.flight_path();
  if (frame.range_m != 0.0 || index >= path.size()) return;
  frame.time_s = path[index].time_s;
  frame.truth = path[index].tanker_from_receiver;
  frame.range_m = (frame.truth.translation_m - dataset.rig().left.tanker_from_camera.translation()).norm();
  frame.region = RegionForRange(frame.range_m);
}

// The bench's StereoBM yardstick, timed between frames spread over the run,
// so that it sees the machine's load as they do.
class YardstickSamples {
 public:
  YardstickSamples(const AnalysisRunOptions& options, const StereoCalibration& calibration, size_t frames)
      : stride_(std::max<size_t>(1, frames / std::max<size_t>(1, options.yardstick_frames))) {
    if (options.yardstick_frames > 0) whole_rectifier_.emplace(calibration);
  }

  // Times the yardstick on frame `index` when it is the analyzed-th frame's turn.
  void After(const OpenedDataset& dataset, const FrameResult& frame, size_t index, size_t analyzed) {
    if (whole_rectifier_ && frame.ok() && analyzed % stride_ == 0) {
      times_ms_.push_back(TimeStereoBmYardstick(dataset, *whole_rectifier_, index));
    }
  }

  // The median time [ms]; none when none was timed.
  std::optional<double> MedianMs() {
    if (times_ms_.empty()) return std::nullopt;
    const auto middle = times_ms_.begin() + static_cast<std::ptrdiff_t>(times_ms_.size() / 2);
    std::nth_element(times_ms_.begin(), middle, times_ms_.end());
    return *middle;
  }

 private:
  std::optional<Rectifier> whole_rectifier_;  // the whole image's
  size_t stride_;
  std::vector<double> times_ms_;
};

}  // namespace

AnalysisRunResult RunAnalysis(const AnalysisRunOptions& requested) {
  const RunInputs in = OpenRunInputs(requested);
  const AnalysisRunOptions& options = in.options;
  const StereoRig& rig = in.dataset.rig();
  const RunCalibration calibration = LoadRunCalibration(options, in.dataset);
  const TriangleMesh mesh = LoadRunReceiver(in);
  ReferenceModel full_surface;  // for FrameAnalysisOptions::pair_sensed_with_full_surface
  const ReferenceModel reference = BuildReferenceModel(mesh, rig, options.reference, &full_surface);
  if (options.progress) {
    std::fprintf(stderr, "reference model '%s': %zu points\n", reference.name.c_str(),
                 reference.points_in_receiver.size());
  }
  const BopObject bop_object(mesh);
  FrameAnalyzer analyzer(calibration.calibration, rig.left.tanker_from_camera, reference, options.frame, &full_surface);
  EnableCorrections(analyzer, in, mesh);
  const nlohmann::json run = RunRecord(in, calibration, reference, bop_object);
  // Written into a staging folder and put in place at the end (output_folder.h).
  std::optional<StagedOutput> staged;
  std::filesystem::path out;
  if (options.write_outputs) {
    staged.emplace(options.out, "run");
    out = staged->path();
    WriteRunInputs(out, calibration, reference);
  }

  AnalysisRunResult result;
  result.reference_points = reference.points_in_receiver.size();
  Progress progress("analyze " + reference.name, in.selected.size());
  TrackHistory history;
  const std::set<size_t> dump_frames(options.dump_frames.begin(), options.dump_frames.end());
  const DumpProjection projection =
      dump_frames.empty() ? DumpProjection{} : DumpProjectionOf(calibration.calibration, rig, reference);
  YardstickSamples yardstick(options, calibration.calibration, in.selected.size());
  for (size_t index : in.selected) {
    FrameDump dump;
    const bool dumped = options.write_outputs && dump_frames.contains(index);
    std::optional<DepthTruth> depth;  // VSD's test depth, where the dataset has it
    FrameResult frame = analyzer.Analyze(in.dataset, index, history, dumped ? &dump : nullptr, &depth);
    if (dumped) WriteFrameDump(out / kFrameDumpDir, index, dump, projection);
    if (frame.ok()) {
      history.before_last = history.last;
      history.last = std::make_pair(frame.time_s, frame.estimate);
    } else {
      FillFromFlightPath(frame, in.dataset, index);
      history = TrackHistory{};
      if (options.progress) std::fprintf(stderr, "frame %zu not measured: %s\n", index, frame.status.c_str());
    }
    yardstick.After(in.dataset, frame, index, result.frames.size());
    ScoreFrame(frame, depth, bop_object, mesh, rig);
    result.frames.push_back(std::move(frame));
    if (options.progress) progress.Advance();
  }
  if (options.progress) progress.Finish();
  result.yardstick_ms = yardstick.MedianMs();
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
