#pragma once
// What the exporters of `aar-analyze export` (dataset_export.h) share: the
// options, the result, reading the selected frames through the dataset
// schema with every file checked against its SHA-256, a run's estimates,
// and writing the output files.

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "aar/analyzer/frame_results.h"
#include "aar/dataset.h"
#include "aar/frame_selection.h"
#include "aar/opened_dataset.h"
#include "aar/stereo_calibration.h"

namespace aar {

struct ExportOptions {
  std::filesystem::path dataset;  ///< dataset folder (read only)
  std::filesystem::path out;      ///< output folder (created; files in it are replaced)
  FrameSelection selection;       ///< frames exported (all by default)
  std::optional<std::filesystem::path>
      run;  ///< tum, rosbag: an `aar-analyze run` folder whose estimates are written too
};

struct ExportResult {
  size_t frames = 0;               ///< frames exported
  std::vector<std::string> files;  ///< files written, relative to `out`, in the order written
  std::vector<std::string> notes;  ///< what was left out and why (e.g. no right-camera depth)
};

/// The dataset as the exporters read it: opened, and the selected frames'
/// sidecars, each checked against the manifest's SHA-256.
struct ExportSource {
  OpenedDataset dataset;
  std::vector<FrameSidecar> frames;  ///< ascending index
};

/// Opens the dataset and reads the sidecars of the selected frames; throws
/// aar::Error as OpenedDataset::Open does, when the dataset has no frames,
/// the selection is empty, or a sidecar is missing, malformed or differs
/// from the manifest's hash.
ExportSource ReadExportSource(const ExportOptions& options);

/// A file of a frame, read and checked against the sidecar's (and the
/// manifest's) SHA-256; throws aar::Error naming the file otherwise.
std::string ReadVerifiedFile(const ExportSource& source, const FileRef& ref);

/// The frames of ExportOptions::run (none without one), ascending; throws
/// aar::Error naming run.json when the run analyzed another dataset
/// (dataset_manifest_sha256), and as ReadFrameResults on a bad frames.csv.
std::vector<FrameResult> ReadRunEstimates(const ExportOptions& options, const ExportSource& source);

/// The dataset's calibration_ideal.yaml, checked against the manifest's
/// SHA-256; throws aar::Error naming it when missing or changed.
StereoCalibration ReadIdealCalibration(const ExportSource& source);

/// The sidecar's file `role` (e.g. "left_depth"); throws aar::Error naming
/// the sidecar and `need` (what to render, e.g. "--depth") when it is absent.
const FileRef& RequireFile(const ExportSource& source, const FrameSidecar& frame, const std::string& role,
                           const std::string& need);

/// Shortest text that reads back as the same double ("0.5", "900", "1e-05"), locale-free.
std::string ShortestDecimal(double value);

/// Writes `bytes` to out/relative atomically (creating folders) and records it in `result`.
void WriteExportFile(const std::filesystem::path& out, const std::string& relative, const std::string& bytes,
                     ExportResult& result);

}  // namespace aar
