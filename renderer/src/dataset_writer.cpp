#include "aar/renderer/dataset_writer.h"

#include <cstdio>
#include <map>
#include <vector>

#include "aar/dataset.h"
#include "aar/error.h"
#include "aar/file_io.h"
#include "aar/folder_lock.h"

namespace aar {
namespace {

// Compares `wanted` with `existing` both ways (objects recursively; a key
// present in one and not the other is a difference); returns
// "key.path: was X, now Y" for the first difference, or "" when equal.
std::string FirstDifference(const nlohmann::json& wanted, const nlohmann::json& existing, const std::string& prefix) {
  const auto where = [&](const std::string& key) { return prefix.empty() ? key : prefix + "." + key; };
  if (wanted.is_object() && existing.is_object()) {
    for (const auto& [key, value] : wanted.items()) {
      if (!existing.contains(key)) return where(key) + ": was absent, now " + value.dump();
      const std::string difference = FirstDifference(value, existing.at(key), where(key));
      if (!difference.empty()) return difference;
    }
    for (const auto& [key, value] : existing.items()) {
      if (!wanted.contains(key)) return where(key) + ": was " + value.dump() + ", now absent";
    }
    return "";
  }
  if (wanted == existing) return "";
  return prefix + ": was " + existing.dump() + ", now " + wanted.dump();
}

// The settings of `kind` to compare: all of them when the dataset already has
// pairs of that kind, else only those both kinds share (the other kind's run
// made the manifest; this kind's section and inputs are new).
nlohmann::json ComparedSettings(const nlohmann::json& manifest, const std::string& kind, bool kind_present) {
  nlohmann::json settings = RenderSettings(manifest, kind);
  if (!kind_present) {
    settings.erase(kind == "calib" ? "calib" : "frames");
    nlohmann::json rig_only = nlohmann::json::object();
    if (settings.at("inputs").contains("rig")) rig_only["rig"] = settings.at("inputs").at("rig");
    settings["inputs"] = rig_only;
  }
  return settings;
}

// True when `dir` exists and holds any entry.
bool HasEntries(const std::filesystem::path& dir) {
  std::error_code ec;
  return std::filesystem::is_directory(dir, ec) && !std::filesystem::is_empty(dir, ec);
}

}  // namespace

nlohmann::json RendererIdentity() { return {{"name", "aar-render"}, {"version", AAR_VERSION}, {"git", AAR_GIT_HASH}}; }

nlohmann::json MergeManifest(const std::filesystem::path& dataset, const std::string& kind,
                             const nlohmann::json& header) {
  const std::filesystem::path path = dataset / kManifestName;
  nlohmann::json manifest = nlohmann::json::object();
  nlohmann::json wanted = header;
  if (std::filesystem::exists(path)) {
    manifest = ReadManifest(dataset).json;
    if (manifest.contains("renderer") && manifest.at("renderer") != header.at("renderer")) {
      // Another build of the renderer (any commit changes the git hash): resume, keep the
      // original identity in the manifest, and say that frames of two builds may be mixed.
      std::fprintf(stderr, "aar-render: warning: %s was started by renderer %s, this is %s; continuing\n",
                   dataset.c_str(), manifest.at("renderer").dump().c_str(), header.at("renderer").dump().c_str());
      wanted["renderer"] = manifest.at("renderer");
    }
    const bool kind_present = manifest.contains(kind == "calib" ? "calib" : "frames");
    const std::string difference = FirstDifference(ComparedSettings(wanted, kind, kind_present),
                                                   ComparedSettings(manifest, kind, kind_present), "");
    if (!difference.empty()) {
      throw Error(path.string() + ": the dataset was made with other settings (" + difference +
                  "); render into a new folder or repeat the original settings");
    }
  } else if (HasEntries(dataset / kFramesDir) || HasEntries(dataset / kCalibDir)) {
    // Without the manifest nothing says which inputs made these frames.
    throw Error(path.string() + ": missing, but " + dataset.string() +
                " holds frames/ or calib/; render into a new folder");
  }
  manifest.merge_patch(wanted);
  if (!manifest.contains("files")) manifest["files"] = nlohmann::json::object();
  if (!manifest.contains("complete")) manifest["complete"] = false;
  return manifest;
}

std::string OpenManifest(const std::filesystem::path& dataset, const std::string& kind, const nlohmann::json& header,
                         const std::function<void()>& write_inputs) {
  const FileLock lock(dataset / kManifestLockName, LockMode::kExclusive);
  const nlohmann::json manifest = MergeManifest(dataset, kind, header);
  write_inputs();
  WriteJsonFile(dataset / kManifestName, manifest);
  return RenderSettingsSha256(manifest, kind);
}

void CopyInput(const std::filesystem::path& dataset, const std::filesystem::path& source, const std::string& name,
               const std::string& sha256) {
  const std::string bytes = ReadFileBytes(source);
  if (Sha256Hex(bytes) != sha256) throw Error(source.string() + ": changed while the run started");
  const std::filesystem::path target = dataset / name;
  if (!std::filesystem::is_regular_file(target) || Sha256File(target) != sha256) WriteFileAtomic(target, bytes);
}

FileLock LockDatasetForWriting(const std::filesystem::path& dataset) {
  FileLock writers = FileLock::TryLock(dataset / kWritersLockName, LockMode::kExclusive);
  if (writers.held()) {
    // No other run is writing: temporaries of interrupted writes are stale.
    for (const char* dir : {"", kFramesDir, kCalibDir}) RemoveStaleTemporaries(dataset / dir);
    writers.Change(LockMode::kShared);
    return writers;
  }
  return FileLock(dataset / kWritersLockName, LockMode::kShared);
}

bool FinalizeManifest(const std::filesystem::path& dataset) {
  const FileLock lock(dataset / kManifestLockName, LockMode::kExclusive);
  Manifest manifest = ReadManifest(dataset);
  nlohmann::json files = nlohmann::json::object();
  bool complete = true;
  for (const char* name :
       {kRigName, kFlightPathName, kReceiverModelName, kBoomModelName, kBoomTubeModelName, kIdealCalibrationName}) {
    if (std::filesystem::is_regular_file(dataset / name)) files[name] = Sha256File(dataset / name);
  }
  const std::pair<const char*, size_t> groups[] = {{"frame", manifest.frame_count},
                                                   {"calib", manifest.calib_pair_count}};
  for (const auto& [kind, count] : groups) {
    for (size_t i = 0; i < count; ++i) {
      const std::filesystem::path sidecar = SidecarPath(dataset, kind, i);
      if (!std::filesystem::is_regular_file(sidecar)) {
        complete = false;
        continue;
      }
      const FrameSidecar s = ReadSidecar(sidecar);
      const std::string& settings =
          kind == std::string("calib") ? manifest.calib_settings_sha256 : manifest.frame_settings_sha256;
      if (!s.settings_sha256.empty() && s.settings_sha256 != settings) {
        throw Error(sidecar.string() + ": rendered with other settings than " + kManifestName +
                    " records (settings_sha256 differs); a dataset of mixed frames cannot be finalized");
      }
      for (const auto& [role, ref] : s.files) files[ref.path] = ref.sha256;
      files[std::filesystem::relative(sidecar, dataset).generic_string()] = Sha256File(sidecar);
    }
  }
  manifest.json["files"] = files;
  manifest.json["complete"] = complete;
  WriteJsonFile(dataset / kManifestName, manifest.json);
  // SHA256SUMS: `sha256sum -c` format (hash, two spaces, path), every listed
  // file and the manifest itself, sorted by path.
  std::map<std::string, std::string> sums;
  for (const auto& [path, hash] : files.items()) sums[path] = hash.get<std::string>();
  sums[kManifestName] = Sha256File(dataset / kManifestName);
  std::string text;
  for (const auto& [path, hash] : sums) text += hash + "  " + path + "\n";
  WriteFileAtomic(dataset / kChecksumsName, text);
  return complete;
}

}  // namespace aar
