#pragma once
// Advisory locks (flock) on a lock file inside a dataset folder, or beside an
// analyzer output folder, so that two processes never write one dataset's
// manifest or one output folder at the same time. flock works across processes on one machine and, on Linux, on NFS
// (emulated with fcntl byte-range locks); Lustre needs the `flock` mount option.

#include <filesystem>
#include <string>

namespace aar {

/// Lock file names inside the locked folder.
inline constexpr const char* kManifestLockName = ".aar-manifest.lock";  ///< dataset: manifest updates
inline constexpr const char* kWritersLockName = ".aar-writers.lock";    ///< dataset: held by every writing run

enum class LockMode {
  kShared,     ///< many holders at once (renders of disjoint frames)
  kExclusive,  ///< one holder
};

/// Holds a flock on `path` (created if needed) for the object's lifetime;
/// closing the descriptor releases it.
class FileLock {
 public:
  /// Waits until the lock is granted; throws aar::Error naming the file when
  /// it cannot be created or locked.
  FileLock(const std::filesystem::path& path, LockMode mode);
  /// Tries once; returns a FileLock that holds nothing (held() false) when
  /// another process holds a conflicting lock.
  static FileLock TryLock(const std::filesystem::path& path, LockMode mode);

  FileLock(FileLock&& other) noexcept;
  FileLock& operator=(FileLock&& other) noexcept;
  FileLock(const FileLock&) = delete;
  FileLock& operator=(const FileLock&) = delete;
  ~FileLock();

  bool held() const { return fd_ >= 0; }
  /// Changes the mode of a held lock (waits; not atomic: flock drops the old
  /// lock before taking the new one).
  void Change(LockMode mode);

 private:
  FileLock() = default;
  int fd_ = -1;
  std::filesystem::path path_;
};

/// The lock file of output folder DIR: PARENT/.NAME.aar-lock, beside it (an
/// output folder is replaced as a whole, output_folder.h; its lock is not).
std::filesystem::path OutputLockPath(const std::filesystem::path& dir);

/// Exclusive lock on OutputLockPath(dir); throws aar::Error naming the folder
/// when another process holds it ("in use by another run").
FileLock LockOutputFolder(const std::filesystem::path& dir);

/// Removes the temporary files of interrupted atomic writes (`.tmp*`, see
/// file_io.h) directly inside `dir`; returns how many were removed. Call only
/// while no other process may be writing into `dir`.
size_t RemoveStaleTemporaries(const std::filesystem::path& dir);

}  // namespace aar
