#include "aar/analyzer/export_source.h"

#include <algorithm>
#include <array>
#include <charconv>

#include "aar/analyzer/run_files.h"
#include "aar/error.h"
#include "aar/file_io.h"
#include "aar/output_folder.h"

namespace aar {

ExportSource ReadExportSource(const ExportOptions& options) {
  ExportSource source{OpenedDataset::Open(options.dataset), {}};
  const Manifest& manifest = source.dataset.manifest();
  const std::string manifest_path = source.dataset.PathOf(kManifestName);
  if (manifest.frame_count == 0) throw Error(manifest_path + ": dataset has no frames");
  const std::vector<size_t> selected = options.selection.Select(manifest.frame_count);
  if (selected.empty()) {
    throw Error(manifest_path + ": no frame selected (the dataset has " + std::to_string(manifest.frame_count) + ")");
  }
  for (size_t index : selected) source.frames.push_back(source.dataset.Sidecar("frame", index));
  return source;
}

std::vector<FrameResult> ReadRunEstimates(const ExportOptions& options, const ExportSource& source) {
  if (!options.run) return {};
  const std::filesystem::path run_json = *options.run / kRunJsonName;
  const std::string manifest_hash = ReadJsonFile(run_json).value("dataset_manifest_sha256", "");
  if (manifest_hash != source.dataset.manifest_sha256()) {
    throw Error(run_json.string() + ": the run analyzed another dataset (dataset_manifest_sha256 differs from " +
                source.dataset.PathOf(kManifestName) + "'s)");
  }
  std::vector<FrameResult> estimates = ReadFrameResults(*options.run / kFramesCsvName);
  std::sort(estimates.begin(), estimates.end(),
            [](const FrameResult& a, const FrameResult& b) { return a.frame < b.frame; });
  return estimates;
}

StereoCalibration ReadIdealCalibration(const ExportSource& source) {
  const std::string path = source.dataset.PathOf(kIdealCalibrationName);
  const std::optional<std::string> yaml = source.dataset.ReadIfPresent(kIdealCalibrationName);
  if (!yaml || !source.dataset.manifest().files.contains(kIdealCalibrationName)) {
    throw Error(path + ": missing, or not listed in manifest.json");
  }
  return ParseCalibration(*yaml, path);
}

std::string ReadVerifiedFile(const ExportSource& source, const FileRef& ref) { return source.dataset.ReadFile(ref); }

const FileRef& RequireFile(const ExportSource& source, const FrameSidecar& frame, const std::string& role,
                           const std::string& need) {
  const auto it = frame.files.find(role);
  if (it == frame.files.end()) {
    throw Error(SidecarPath(source.dataset.folder(), "frame", frame.index).string() + ": no " + role +
                " (render with " + need + ")");
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

}  // namespace aar
