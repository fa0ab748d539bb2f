#include "aar/file_io.h"

#include <fcntl.h>
#include <openssl/evp.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>

#include "aar/error.h"

namespace aar {
namespace {

std::filesystem::path TemporaryName(const std::filesystem::path& path) {
  // Keeps the extension, so writers that pick a format from the name still work.
  return path.parent_path() / (".tmp" + std::to_string(::getpid()) + "." + path.filename().string());
}

void Rename(const std::filesystem::path& from, const std::filesystem::path& to) {
  std::error_code ec;
  std::filesystem::rename(from, to, ec);
  if (ec) {
    std::filesystem::remove(from, ec);
    throw Error(to.string() + ": cannot rename temporary file into place");
  }
}

// True when `path` is a regular file holding exactly `bytes`.
bool HoldsBytes(const std::filesystem::path& path, std::string_view bytes) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec) || std::filesystem::file_size(path, ec) != bytes.size() || ec) {
    return false;
  }
  std::ifstream in(path, std::ios::binary);
  std::string existing(bytes.size(), '\0');
  return in.read(existing.data(), static_cast<std::streamsize>(existing.size())) && existing == bytes;
}

}  // namespace

void WriteFileAtomic(const std::filesystem::path& path, std::string_view bytes) {
  if (HoldsBytes(path, bytes)) return;  // already there: the file, its time stamps included, stays untouched
  const std::filesystem::path temporary = TemporaryName(path);
  const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw Error(path.string() + ": cannot write (" + std::strerror(errno) + ")");
  size_t written = 0;
  while (written < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + written, bytes.size() - written);
    if (n <= 0) {
      ::close(fd);
      std::filesystem::remove(temporary);
      throw Error(path.string() + ": write failed (" + std::strerror(errno) + ")");
    }
    written += static_cast<size_t>(n);
  }
  if (::fsync(fd) != 0 || ::close(fd) != 0) {
    std::filesystem::remove(temporary);
    throw Error(path.string() + ": write failed (" + std::strerror(errno) + ")");
  }
  Rename(temporary, path);
}

void WriteFileAtomicWith(const std::filesystem::path& path,
                         const std::function<void(const std::filesystem::path&)>& write) {
  const std::filesystem::path temporary = TemporaryName(path);
  try {
    write(temporary);
    std::error_code ec;
    if (std::filesystem::is_regular_file(path, ec) && HoldsBytes(path, ReadFileBytes(temporary))) {
      std::filesystem::remove(temporary);  // already there: left untouched
      return;
    }
  } catch (...) {
    std::error_code ec;
    std::filesystem::remove(temporary, ec);
    throw;
  }
  Rename(temporary, path);
}

void CheckRegularFile(const std::filesystem::path& path, const std::string& what) {
  // A FIFO or a device would block or never end: only regular files are read.
  struct stat info {};
  if (::stat(path.c_str(), &info) != 0) {
    if (errno == ENOENT) throw Error(path.string() + ": " + what + " not found");
    throw Error(path.string() + ": cannot open (" + std::strerror(errno) + ")");
  }
  if (S_ISDIR(info.st_mode)) throw Error(path.string() + ": is a folder, not a file");
  if (!S_ISREG(info.st_mode)) throw Error(path.string() + ": not a regular file (a FIFO, socket or device)");
}

std::string ReadFileBytes(const std::filesystem::path& path) {
  CheckRegularFile(path, "file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path.string() + ": cannot open (" + std::strerror(errno) + ")");
  std::ostringstream out;
  out << in.rdbuf();
  if (in.bad()) throw Error(path.string() + ": read failed");
  return out.str();
}

std::string Sha256Hex(std::string_view bytes) {
  unsigned char digest[EVP_MAX_MD_SIZE];
  unsigned int length = 0;
  if (EVP_Digest(bytes.data(), bytes.size(), digest, &length, EVP_sha256(), nullptr) != 1) {
    throw Error("SHA-256 computation failed");
  }
  static const char* kHex = "0123456789abcdef";
  std::string hex;
  hex.reserve(2 * length);
  for (unsigned int i = 0; i < length; ++i) {
    hex.push_back(kHex[digest[i] >> 4]);
    hex.push_back(kHex[digest[i] & 15]);
  }
  return hex;
}

std::string Sha256File(const std::filesystem::path& path) { return Sha256Hex(ReadFileBytes(path)); }

void EnsureWritableDirectory(const std::filesystem::path& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec || !std::filesystem::is_directory(dir)) {
    throw Error(dir.string() + ": cannot create output folder (" + ec.message() + ")");
  }
  if (::access(dir.c_str(), W_OK) != 0) throw Error(dir.string() + ": output folder is not writable");
}

}  // namespace aar
