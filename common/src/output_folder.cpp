#include "aar/output_folder.h"

#include <fcntl.h>
#include <stdio.h>

#include <cerrno>
#include <cstring>
#include <nlohmann/json.hpp>

#include "aar/dataset.h"
#include "aar/error.h"
#include "aar/file_io.h"

namespace aar {
namespace {

namespace fs = std::filesystem;

// Output folders written before the marker existed hold this lock file.
constexpr const char* kEarlierOutputLockName = ".aar-output.lock";

// The folder itself, absolute, with symbolic links of its existing part resolved.
fs::path Resolved(const fs::path& out) {
  std::error_code ec;
  fs::path resolved = fs::weakly_canonical(fs::absolute(out, ec), ec);
  if (ec) throw Error(out.string() + ": cannot resolve the output folder (" + ec.message() + ")");
  if (!resolved.has_filename()) resolved = resolved.parent_path();
  return resolved;
}

bool IsDatasetFolder(const fs::path& dir) {
  std::error_code ec;
  if (!fs::is_regular_file(dir / kManifestName, ec)) return false;
  try {
    const nlohmann::json manifest = ReadJsonFile(dir / kManifestName);
    return manifest.is_object() && manifest.value("schema", "").starts_with("aar-dataset/");
  } catch (const Error&) {
    return false;  // not a manifest of ours
  }
}

fs::path Beside(const fs::path& out, const std::string& suffix) {
  return out.parent_path() / ("." + out.filename().string() + suffix);
}

void RemoveAll(const fs::path& path) {
  std::error_code ec;
  fs::remove_all(path, ec);
  if (ec) throw Error(path.string() + ": cannot remove (" + ec.message() + ")");
}

void RenameOrThrow(const fs::path& from, const fs::path& to) {
  std::error_code ec;
  fs::rename(from, to, ec);
  if (ec) throw Error(to.string() + ": cannot move the output into place (" + ec.message() + ")");
}

}  // namespace

FileLock StagedOutput::CheckAndLock(const fs::path& out, const fs::path& resolved) {
  CheckOutputFolder(out);
  EnsureWritableDirectory(resolved.parent_path());
  return LockOutputFolder(resolved);
}

void CheckOutputFolder(const fs::path& out) {
  const fs::path resolved = Resolved(out);
  for (fs::path dir = resolved;; dir = dir.parent_path()) {
    if (IsDatasetFolder(dir)) {
      throw Error(out.string() + ": " + (dir == resolved ? "is the dataset " : "is inside the dataset ") +
                  dir.string() + "; choose an --out outside any dataset");
    }
    if (dir == dir.parent_path()) break;
  }
  std::error_code ec;
  const fs::file_status status = fs::status(resolved, ec);
  if (!fs::exists(status)) return;
  if (!fs::is_directory(status)) throw Error(out.string() + ": exists and is not a folder");
  if (fs::is_empty(resolved, ec) || fs::exists(resolved / kOutputMarkerName, ec) ||
      fs::exists(resolved / kEarlierOutputLockName, ec)) {
    return;
  }
  throw Error(out.string() +
              ": holds files that aar-analyze did not write; choose a new or empty --out (an output folder is "
              "replaced as a whole)");
}

StagedOutput::StagedOutput(const fs::path& out, const std::string& command)
    : out_(Resolved(out)), command_(command), lock_(CheckAndLock(out, out_)) {
  CheckOutputFolder(out);  // again under the lock: another command may have committed meanwhile
  staging_ = Beside(out_, ".aar-staging");
  old_ = Beside(out_, ".aar-old");
  // What a killed command left: its staging folder, or (the fallback's window)
  // the previous output moved aside before the new one took its place.
  std::error_code ec;
  if (fs::exists(old_, ec)) {
    if (fs::exists(out_, ec)) {
      RemoveAll(old_);
    } else {
      RenameOrThrow(old_, out_);
    }
  }
  RemoveAll(staging_);
  if (!fs::create_directory(staging_, ec) || ec) {
    throw Error(staging_.string() + ": cannot create (" + ec.message() + ")");
  }
}

StagedOutput::~StagedOutput() {
  if (committed_ || staging_.empty()) return;
  std::error_code ec;
  fs::remove_all(staging_, ec);
}

void StagedOutput::Commit() {
  WriteFileAtomic(staging_ / kOutputMarkerName,
                  nlohmann::json({{"tool", "aar-analyze"}, {"command", command_}}).dump(2) + "\n");
  std::error_code ec;
  if (!fs::exists(out_, ec)) {
    RenameOrThrow(staging_, out_);
  } else if (::renameat2(AT_FDCWD, staging_.c_str(), AT_FDCWD, out_.c_str(), RENAME_EXCHANGE) == 0) {
    RemoveAll(staging_);  // now the previous output
  } else if (errno == EINVAL || errno == ENOSYS) {
    // A file system without the exchange: two renames; a kill between them
    // leaves the previous output at old_, which the next command puts back.
    RenameOrThrow(out_, old_);
    RenameOrThrow(staging_, out_);
    RemoveAll(old_);
  } else {
    throw Error(out_.string() + ": cannot move the output into place (" + std::strerror(errno) + ")");
  }
  committed_ = true;
}

}  // namespace aar
