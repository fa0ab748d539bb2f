#pragma once
// `aar-analyze run`, `calibrate`, `reference` and `merge` as library calls:
// check the inputs that make a run possible (manifest, calibration, receiver
// model) before writing anything, then analyze the selected frames and write
// the per-frame CSV and the per-region summary (docs/analysis.md).

#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "aar/analyzer/calibration.h"
#include "aar/analyzer/frame_analysis.h"
#include "aar/analyzer/pose_filter.h"
#include "aar/analyzer/reference_model.h"
#include "aar/analyzer/run_files.h"
#include "aar/frame_selection.h"

namespace aar {

struct ReferenceRequest {
  std::string model = "shelled";  ///< "full" or "shelled"
  ReferenceModelOptions options;  ///< sampling and shelling settings
};

/// Builds the reference cloud from a receiver mesh and a rig; throws on an unknown model name.
/// `full_out`, when given, receives the full model the shell was cut from (or the model itself).
ReferenceModel BuildReferenceModel(const TriangleMesh& mesh, const StereoRig& rig, const ReferenceRequest& request,
                                   ReferenceModel* full_out = nullptr);

struct CalibrateOutput {
  CalibrationResult result;
  nlohmann::json report;  ///< calibration_report.json content (deterministic)
};

/// Calibrates from the dataset's calib/ pairs and returns the result plus its JSON report.
CalibrateOutput CalibrateDataset(const OpenedDataset& dataset, const CalibrationOptions& options);

/// Writes calibration.yaml and calibration_report.json into `out`.
void WriteCalibrationOutputs(const std::filesystem::path& out, const CalibrateOutput& calibration);

struct AnalysisRunOptions {
  std::filesystem::path dataset;                        ///< dataset folder (docs/dataset-format.md)
  std::filesystem::path out;                            ///< output folder (created)
  std::optional<std::filesystem::path> calibration;     ///< OpenCV YAML; none = calibrate from DATASET/calib
  std::optional<std::filesystem::path> receiver_model;  ///< none = DATASET/receiver.glb
  ReferenceRequest reference;
  CalibrationOptions calibration_options;
  Preset preset = Preset::kDefault;  ///< recorded in run.json; `frame` holds its options
  FrameAnalysisOptions frame;        ///< its mask_boom and mask_propellers are set from the two below
  /// Remove the boom's pixels / the propellers' points (FrameAnalysisOptions::mask_boom, mask_propellers);
  /// none: on with the default preset when the dataset has them (manifest.json's inputs.boom_model;
  /// frames.propellers with rpm > 0), off otherwise.
  std::optional<bool> mask_boom;
  std::optional<bool> mask_propellers;
  PoseFilterOptions filter;  ///< the temporal filter over the analyzed frames (frames.csv's filt_* columns)
  FrameSelection selection;
  bool progress = true;       ///< progress line and per-frame failures on stderr
  bool write_outputs = true;  ///< false for `bench`: time only
  /// `bench`: also time the speed targets' yardstick (bench_yardstick.h) on
  /// up to this many of the measured frames (0: not).
  size_t yardstick_frames = 0;
  /// Frames whose disparity, clouds and overlay are written into OUT/frames/ (frame_dump.h).
  std::vector<size_t> dump_frames;
};

struct AnalysisRunResult {
  std::vector<FrameResult> frames;
  ModelSummary summary;
  size_t reference_points = 0;
  std::optional<double> yardstick_ms;  ///< options.yardstick_frames > 0: TimeStereoBmYardstick's median
};

AnalysisRunResult RunAnalysis(const AnalysisRunOptions& options);

/// Combines the frames.csv of shard run folders into `out` with the same
/// frames.csv, summary.json and summary.md a single run gives. The temporal
/// filter runs again over the merged frames (a shard's filter saw only its own). Throws when
/// the shards differ in model or dataset, or overlap.
void MergeRuns(const std::vector<std::filesystem::path>& shard_dirs, const std::filesystem::path& out);

}  // namespace aar
