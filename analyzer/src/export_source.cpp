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

}  // namespace aar
