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

// Compares `wanted` against `existing` key by key (objects recursively, keys
// missing from `existing` are new sections and fine); returns
// "key.path: was X, now Y" for the first difference, or "" when compatible.
std::string FirstMismatch(const nlohmann::json& wanted, const nlohmann::json& existing, const std::string& prefix) {
  if (wanted.is_object() && existing.is_object()) {
    for (const auto& [key, value] : wanted.items()) {
      if (!existing.contains(key)) continue;
      const std::string where = FirstMismatch(value, existing.at(key), prefix.empty() ? key : prefix + "." + key);
      if (!where.empty()) return where;
    }
    return "";
  }
  if (wanted == existing) return "";
  return prefix + ": was " + existing.dump() + ", now " + wanted.dump();
}

// True when `dir` exists and holds any entry.
bool HasEntries(const std::filesystem::path& dir) {
  std::error_code ec;
  return std::filesystem::is_directory(dir, ec) && !std::filesystem::is_empty(dir, ec);
}

}  // namespace

nlohmann::json RendererIdentity() { return {{"name", "aar-render"}, {"version", AAR_VERSION}, {"git", AAR_GIT_HASH}}; }

nlohmann::json MergeManifest(const std::filesystem::path& dataset, const nlohmann::json& header) {
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
    const std::string mismatch = FirstMismatch(wanted, manifest, "");
    if (!mismatch.empty()) {
      throw Error(path.string() + ": the dataset was made with other settings (" + mismatch +
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

void OpenManifest(const std::filesystem::path& dataset, const nlohmann::json& header,
                  const std::function<void()>& write_inputs) {
  const FileLock lock(dataset / kManifestLockName, LockMode::kExclusive);
  const nlohmann::json manifest = MergeManifest(dataset, header);
  write_inputs();
  WriteJsonFile(dataset / kManifestName, manifest);
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
