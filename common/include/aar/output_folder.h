#pragma once
// An output folder written as a unit (docs/exit-codes.md). A command writes
// into a hidden staging folder beside OUT and commits it with one rename
// (Linux renameat2 RENAME_EXCHANGE when OUT exists), so OUT always holds the
// previous command's complete output or the new one's, never a mix, whatever
// kills the process. OUT is never a dataset or inside one, and a folder the
// tool did not write is never replaced.
//
//   PARENT/OUT/                 the output; holds kOutputMarkerName
//   PARENT/.OUT.aar-lock        flock of the commands writing OUT (folder_lock.h)
//   PARENT/.OUT.aar-staging/    the output being written (removed on failure,
//                               and by the next command when a kill left it)

#include <filesystem>
#include <string>

#include "aar/folder_lock.h"

namespace aar {

/// The file every committed output folder holds (the command that wrote it).
inline constexpr const char* kOutputMarkerName = ".aar-output";

/// Throws aar::Error unless `out` may receive an output: not a dataset folder
/// nor inside one (a folder with a manifest.json of schema aar-dataset/...),
/// and absent, an empty folder, or an output this tool wrote. Writes nothing.
void CheckOutputFolder(const std::filesystem::path& out);

class StagedOutput {
 public:
  /// CheckOutputFolder, then creates OUT's parent if needed, takes OUT's lock
  /// (throws when another command holds it), clears what a killed command
  /// left beside OUT, and creates an empty staging folder.
  StagedOutput(const std::filesystem::path& out, const std::string& command);
  /// Removes the staging folder unless Commit() ran.
  ~StagedOutput();
  StagedOutput(const StagedOutput&) = delete;
  StagedOutput& operator=(const StagedOutput&) = delete;

  /// Where the command writes its files.
  const std::filesystem::path& path() const { return staging_; }
  /// Writes the marker and puts the staging folder in OUT's place in one
  /// rename; the previous output, if any, is removed afterwards.
  void Commit();

 private:
  static FileLock CheckAndLock(const std::filesystem::path& out, const std::filesystem::path& resolved);

  std::filesystem::path out_;
  std::filesystem::path staging_;
  std::filesystem::path old_;  // the previous output, where the fallback without RENAME_EXCHANGE moves it
  std::string command_;
  FileLock lock_;
  bool committed_ = false;
};

}  // namespace aar
