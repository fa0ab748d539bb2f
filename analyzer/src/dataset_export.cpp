#include "aar/analyzer/dataset_export.h"

#include <algorithm>
#include <array>
#include <charconv>

#include "aar/analyzer/analysis_run.h"
#include "aar/analyzer/export_bop.h"
#include "aar/analyzer/export_middlebury.h"
#include "aar/analyzer/export_ros.h"
#include "aar/analyzer/export_rosbag.h"
#include "aar/analyzer/export_tum.h"
#include "aar/error.h"
#include "aar/file_io.h"
#include "aar/output_folder.h"

namespace aar {

std::string ToString(ExportFormat format) {
  switch (format) {
    case ExportFormat::kBop:
      return "bop";
    case ExportFormat::kMiddlebury:
      return "middlebury";
    case ExportFormat::kTum:
      return "tum";
    case ExportFormat::kRos:
      return "ros";
    case ExportFormat::kRosbag:
      return "rosbag";
  }
  return "bop";
}

ExportFormat ParseExportFormat(const std::string& text) {
  for (ExportFormat f :
       {ExportFormat::kBop, ExportFormat::kMiddlebury, ExportFormat::kTum, ExportFormat::kRos, ExportFormat::kRosbag}) {
    if (text == ToString(f)) return f;
  }
  throw Error("--format '" + text + "': expected bop, middlebury, tum, ros or rosbag");
}

ExportSource ReadExportSource(const ExportOptions& options) {
  ExportSource source;
  source.dataset = options.dataset;
  source.manifest = ReadManifest(options.dataset);
  const std::string manifest_path = (options.dataset / kManifestName).string();
  if (source.manifest.frame_count == 0) throw Error(manifest_path + ": dataset has no frames");
  const std::vector<size_t> selected = options.selection.Select(source.manifest.frame_count);
  if (selected.empty()) {
    throw Error(manifest_path + ": no frame selected (the dataset has " + std::to_string(source.manifest.frame_count) +
                ")");
  }
  for (size_t index : selected)
    source.frames.push_back(ReadListedSidecar(options.dataset, source.manifest, "frame", index));
  return source;
}

std::vector<FrameResult> ReadRunEstimates(const ExportOptions& options) {
  if (!options.run) return {};
  const std::filesystem::path run_json = *options.run / kRunJsonName;
  const std::string manifest_hash = ReadJsonFile(run_json).value("dataset_manifest_sha256", "");
  if (manifest_hash != Sha256File(options.dataset / kManifestName)) {
    throw Error(run_json.string() + ": the run analyzed another dataset (dataset_manifest_sha256 differs from " +
                (options.dataset / kManifestName).string() + "'s)");
  }
  std::vector<FrameResult> estimates = ReadFrameResults(*options.run / kFramesCsvName);
  std::sort(estimates.begin(), estimates.end(),
            [](const FrameResult& a, const FrameResult& b) { return a.frame < b.frame; });
  return estimates;
}

StereoCalibration ReadIdealCalibration(const ExportSource& source) {
  const std::filesystem::path yaml = source.dataset / kIdealCalibrationName;
  if (const auto it = source.manifest.files.find(kIdealCalibrationName);
      it == source.manifest.files.end() || !std::filesystem::is_regular_file(yaml) || Sha256File(yaml) != it->second) {
    throw Error(yaml.string() + ": missing, or its SHA-256 differs from manifest.json's");
  }
  return ReadCalibration(yaml);
}

std::string ReadVerifiedFile(const ExportSource& source, const FileRef& ref) {
  return ReadListedFile(source.dataset, source.manifest, ref);
}

const FileRef& RequireFile(const ExportSource& source, const FrameSidecar& frame, const std::string& role,
                           const std::string& need) {
  const auto it = frame.files.find(role);
  if (it == frame.files.end()) {
    throw Error(SidecarPath(source.dataset, "frame", frame.index).string() + ": no " + role + " (render with " + need +
                ")");
  }
  return it->second;
}

std::string ShortestDecimal(double value) {
  if (value == 0.0) return "0";  // also -0
  std::array<char, 32> buffer{};
  const auto [end, error] = std::to_chars(buffer.data(), buffer.data() + buffer.size(), value);
  if (error != std::errc()) throw Error("cannot format a number");
  return std::string(buffer.data(), end);
}

void WriteExportFile(const std::filesystem::path& out, const std::string& relative, const std::string& bytes,
                     ExportResult& result) {
  const std::filesystem::path path = out / relative;
  EnsureWritableDirectory(path.parent_path());
  WriteFileAtomic(path, bytes);
  result.files.push_back(relative);
}

namespace {

ExportResult ExportInto(ExportFormat format, const ExportOptions& options) {
  switch (format) {
    case ExportFormat::kBop:
      return ExportBop(options);
    case ExportFormat::kMiddlebury:
      return ExportMiddlebury(options);
    case ExportFormat::kTum:
      return ExportTum(options);
    case ExportFormat::kRos:
      return ExportRos(options);
    case ExportFormat::kRosbag:
      return ExportRosbag(options);
  }
  throw Error("export: unknown format");
}

}  // namespace

ExportResult ExportDataset(ExportFormat format, const ExportOptions& options) {
  if (options.out.empty()) throw Error("export: no output folder given (--out)");
  CheckOutputFolder(options.out);
  if (options.run) {
    std::error_code ec;
    const std::filesystem::path run = std::filesystem::weakly_canonical(*options.run, ec);
    const std::filesystem::path out = std::filesystem::weakly_canonical(options.out, ec);
    if (std::mismatch(out.begin(), out.end(), run.begin(), run.end()).first == out.end()) {
      throw Error(options.out.string() + ": --out is the --run folder or holds it; export into another folder");
    }
  }
  ReadExportSource(options);  // the dataset and its frames, checked before anything is written
  // Written as a whole (output_folder.h): a failed or killed export leaves the previous output.
  StagedOutput staged(options.out, "export");
  ExportOptions into = options;
  into.out = staged.path();
  ExportResult result = ExportInto(format, into);
  staged.Commit();
  return result;
}

}  // namespace aar
