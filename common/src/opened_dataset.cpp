#include "aar/opened_dataset.h"

#include <utility>

#include "aar/error.h"
#include "aar/file_io.h"
#include "aar/json_file.h"

namespace aar {
namespace {

// The SHA-256s the manifest records for the render input `name` (manifest
// key `key`): its entry in `files`, and inputs.<key>.sha256 when inputs.<key>
// names the file.
std::vector<std::string> RecordedHashes(const Manifest& manifest, const std::string& key, const std::string& name,
                                        const std::string& manifest_path) {
  std::vector<std::string> hashes;
  if (const auto it = manifest.files.find(name); it != manifest.files.end()) hashes.push_back(it->second);
  if (!manifest.json.contains("inputs") || !manifest.json.at("inputs").is_object()) return hashes;
  const nlohmann::json& inputs = manifest.json.at("inputs");
  if (!inputs.contains(key) || !inputs.at(key).is_object()) return hashes;
  const nlohmann::json& input = inputs.at(key);
  if (!input.contains("file") || input.at("file") != name || !input.contains("sha256")) return hashes;
  if (!input.at("sha256").is_string()) throw Error(manifest_path + ": inputs." + key + ".sha256 is not a string");
  hashes.push_back(input.at("sha256").get<std::string>());
  return hashes;
}

std::string SidecarRelative(const std::string& kind, size_t index) {
  return std::string(kind == "calib" ? kCalibDir : kFramesDir) + "/" + FrameStem(index) + ".json";
}

}  // namespace

OpenedDataset OpenedDataset::Open(const std::filesystem::path& folder) {
  OpenedDataset d;
  d.folder_ = folder;
  const std::string manifest_path = d.PathOf(kManifestName);
  if (!std::filesystem::is_regular_file(folder / kManifestName)) {
    throw Error(manifest_path + ": no manifest (is '" + folder.string() + "' a dataset folder?)");
  }
  const std::string manifest_text = ReadFileBytes(folder / kManifestName);
  d.manifest_sha256_ = Sha256Hex(manifest_text);
  d.manifest_ = ParseManifest(ParseJsonText(manifest_text, manifest_path), manifest_path);
  // The dataset's copies of the render inputs must be the files the manifest
  // recorded, or an analysis would silently use another rig, flight path or
  // model than the images were made with.
  const std::pair<const char*, const char*> inputs[] = {{"rig", kRigName},
                                                        {"flight_path", kFlightPathName},
                                                        {"receiver_model", kReceiverModelName},
                                                        {"boom_model", kBoomModelName},
                                                        {"boom_tube_model", kBoomTubeModelName}};
  for (const auto& [key, name] : inputs) {
    const std::vector<std::string> hashes = RecordedHashes(d.manifest_, key, name, manifest_path);
    const std::filesystem::path file = folder / name;
    if (!std::filesystem::is_regular_file(file)) {
      const bool optional = std::string(name) == kFlightPathName || std::string(name) == kReceiverModelName;
      if (!hashes.empty() && !optional) throw Error(file.string() + ": missing (manifest.json records it)");
      continue;
    }
    std::string bytes = ReadFileBytes(file);
    if (!hashes.empty()) {
      const std::string actual = Sha256Hex(bytes);
      for (const std::string& hash : hashes) {
        if (hash != actual) {
          throw Error(file.string() +
                      ": SHA-256 differs from manifest.json's (changed after rendering; restore it or "
                      "render again)");
        }
      }
    }
    if (std::string(name) == kRigName) {
      d.rig_ = RigFromJson(ParseJsonText(bytes, file.string()), file.string());
    } else if (std::string(name) == kFlightPathName) {
      d.flight_path_ = ParseFlightPath(bytes, file.string());
      if (d.flight_path_.size() != d.manifest_.frame_count) {
        throw Error(manifest_path + ": frames.count " + std::to_string(d.manifest_.frame_count) + " differs from the " +
                    std::to_string(d.flight_path_.size()) + " samples of " + file.string());
      }
    } else {
      d.inputs_[name] = std::move(bytes);
    }
  }
  return d;
}

std::string OpenedDataset::PathOf(const std::string& relative) const { return (folder_ / relative).string(); }

const StereoRig& OpenedDataset::rig() const {
  if (!rig_) throw Error(PathOf(kRigName) + ": file not found");
  return *rig_;
}

const std::string* OpenedDataset::Input(const std::string& name) const {
  const auto it = inputs_.find(name);
  return it == inputs_.end() ? nullptr : &it->second;
}

FrameSidecar OpenedDataset::Sidecar(const std::string& kind, size_t index) const {
  const std::string relative = SidecarRelative(kind, index);
  const std::filesystem::path path = folder_ / relative;
  if (!std::filesystem::is_regular_file(path)) throw Error(path.string() + ": sidecar missing (not rendered)");
  CheckListed(kind, index);
  const auto listed = manifest_.files.find(relative);
  const std::string bytes = ReadFileBytes(path);
  if (listed != manifest_.files.end() && listed->second != Sha256Hex(bytes)) {
    throw Error(path.string() + ": SHA-256 differs from manifest.json's");
  }
  FrameSidecar sidecar = ParseSidecar(ParseJsonText(bytes, path.string()), path.string());
  const std::string& settings = kind == "calib" ? manifest_.calib_settings_sha256 : manifest_.frame_settings_sha256;
  if (!settings.empty() && !sidecar.settings_sha256.empty() && sidecar.settings_sha256 != settings) {
    throw Error(path.string() + ": rendered with other settings than manifest.json records");
  }
  if (sidecar.kind != kind || sidecar.index != index) {
    throw Error(path.string() + ": holds " + sidecar.kind + " " + std::to_string(sidecar.index) + ", not " + kind +
                " " + std::to_string(index));
  }
  return sidecar;
}

void OpenedDataset::CheckListed(const std::string& kind, size_t index) const {
  const std::string relative = SidecarRelative(kind, index);
  if (manifest_.complete && !manifest_.files.contains(relative)) {
    throw Error(PathOf(kManifestName) + ": complete, but 'files' does not list " + relative);
  }
}

std::string OpenedDataset::ReadFile(const FileRef& ref) const {
  const std::filesystem::path path = folder_ / ref.path;
  if (!std::filesystem::is_regular_file(path)) throw Error(path.string() + ": missing");
  std::string bytes = ReadFileBytes(path);
  const std::string hash = Sha256Hex(bytes);
  if (hash != ref.sha256) {
    throw Error(path.string() + ": SHA-256 differs from the sidecar's (file changed or truncated)");
  }
  if (const auto it = manifest_.files.find(ref.path); it != manifest_.files.end() && it->second != hash) {
    throw Error(path.string() + ": SHA-256 differs from manifest.json's");
  }
  return bytes;
}

std::optional<std::string> OpenedDataset::ReadIfPresent(const std::string& relative) const {
  const std::filesystem::path path = folder_ / relative;
  if (!std::filesystem::is_regular_file(path)) return std::nullopt;
  std::string bytes = ReadFileBytes(path);
  if (const auto it = manifest_.files.find(relative); it != manifest_.files.end() && Sha256Hex(bytes) != it->second) {
    throw Error(path.string() + ": SHA-256 differs from manifest.json's");
  }
  return bytes;
}

}  // namespace aar
