#pragma once
// Atomic file writes and content hashes. Every output file is written to a
// temporary name beside its destination and renamed, so an interrupted run
// never leaves a truncated file under the final name.

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace aar {

/// Writes `bytes` to `path` atomically (temporary file + fsync + rename). A
/// file that already holds exactly these bytes is left untouched (so a
/// command that changes nothing changes no time stamp either).
void WriteFileAtomic(const std::filesystem::path& path, std::string_view bytes);

/// Lets `write` create the temporary file at the given path, then renames it
/// to `path` (unless `path` already holds the same bytes); for writers (PNG,
/// EXR, YAML) that want a file name.
void WriteFileAtomicWith(const std::filesystem::path& path,
                         const std::function<void(const std::filesystem::path& temporary)>& write);

/// Throws aar::Error "<path>: <what> not found" when nothing is there, or
/// names the reason when `path` cannot be a readable file (a name too long, a
/// loop of symbolic links, a folder, a FIFO or device).
void CheckRegularFile(const std::filesystem::path& path, const std::string& what);

/// Reads a whole regular file; throws aar::Error naming the file (CheckRegularFile).
std::string ReadFileBytes(const std::filesystem::path& path);

/// Lower-case hex SHA-256 of bytes / of a file's content.
std::string Sha256Hex(std::string_view bytes);
std::string Sha256File(const std::filesystem::path& path);

/// Checks that `dir` exists (creating it and its parents if needed) and is
/// writable; throws aar::Error naming the folder otherwise.
void EnsureWritableDirectory(const std::filesystem::path& dir);

}  // namespace aar
