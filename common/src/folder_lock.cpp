#include "aar/folder_lock.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <utility>

#include "aar/error.h"

namespace aar {
namespace {

int OpenLockFile(const std::filesystem::path& path) {
  const int fd = ::open(path.c_str(), O_CREAT | O_RDWR | O_CLOEXEC, 0644);
  if (fd < 0) throw Error(path.string() + ": cannot create lock file (" + std::strerror(errno) + ")");
  return fd;
}

int Operation(LockMode mode) { return mode == LockMode::kShared ? LOCK_SH : LOCK_EX; }

// flock, retried when a signal interrupts the wait.
int Flock(int fd, int operation) {
  int rc = 0;
  do {
    rc = ::flock(fd, operation);
  } while (rc != 0 && errno == EINTR);
  return rc;
}

}  // namespace

FileLock::FileLock(const std::filesystem::path& path, LockMode mode) : fd_(OpenLockFile(path)), path_(path) {
  if (Flock(fd_, Operation(mode)) != 0) {
    const std::string reason = std::strerror(errno);
    ::close(fd_);
    fd_ = -1;
    throw Error(path.string() + ": cannot lock (" + reason + ")");
  }
}

FileLock FileLock::TryLock(const std::filesystem::path& path, LockMode mode) {
  FileLock lock;
  const int fd = OpenLockFile(path);
  if (Flock(fd, Operation(mode) | LOCK_NB) != 0) {
    const int error = errno;
    ::close(fd);
    if (error == EWOULDBLOCK) return lock;
    throw Error(path.string() + ": cannot lock (" + std::strerror(error) + ")");
  }
  lock.fd_ = fd;
  lock.path_ = path;
  return lock;
}

FileLock::FileLock(FileLock&& other) noexcept : fd_(std::exchange(other.fd_, -1)), path_(std::move(other.path_)) {}

FileLock& FileLock::operator=(FileLock&& other) noexcept {
  if (this != &other) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = std::exchange(other.fd_, -1);
    path_ = std::move(other.path_);
  }
  return *this;
}

FileLock::~FileLock() {
  if (fd_ >= 0) ::close(fd_);
}

void FileLock::Change(LockMode mode) {
  if (fd_ < 0) throw Error(path_.string() + ": lock not held");
  if (Flock(fd_, Operation(mode)) != 0) throw Error(path_.string() + ": cannot lock (" + std::strerror(errno) + ")");
}

std::filesystem::path OutputLockPath(const std::filesystem::path& dir) {
  // The folder's own path (symbolic links resolved), so that every name of one folder locks one file.
  std::error_code ec;
  std::filesystem::path absolute = std::filesystem::weakly_canonical(std::filesystem::absolute(dir, ec), ec);
  if (ec) absolute = std::filesystem::absolute(dir).lexically_normal();
  const std::filesystem::path folder = absolute.has_filename() ? absolute : absolute.parent_path();
  return folder.parent_path() / ("." + folder.filename().string() + ".aar-lock");
}

FileLock LockOutputFolder(const std::filesystem::path& dir) {
  const std::filesystem::path path = OutputLockPath(dir);
  FileLock lock = FileLock::TryLock(path, LockMode::kExclusive);
  if (!lock.held()) {
    throw Error(dir.string() + ": output folder in use by another run (" + path.string() +
                " is locked); wait for it or choose another --out");
  }
  return lock;
}

size_t RemoveStaleTemporaries(const std::filesystem::path& dir) {
  size_t removed = 0;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) {
    if (entry.path().filename().string().starts_with(".tmp") && entry.is_regular_file(ec)) {
      if (std::filesystem::remove(entry.path(), ec)) ++removed;
    }
  }
  return removed;
}

}  // namespace aar
