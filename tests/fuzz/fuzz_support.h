#pragma once
// Shared by the libFuzzer harnesses: the readers under test take file paths,
// so each input is written to a file in a per-process scratch folder first.
// A harness catches aar::Error (the readers' one way to refuse input); any
// other exception escapes, std::terminate aborts, and libFuzzer reports it as
// a crash, like a sanitizer finding: every refusal must be a named aar::Error.

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

namespace aar::fuzz {

/// The scratch folder of this process, in memory (/dev/shm) where there is
/// one: a disk-backed /tmp makes the harnesses some 20 times slower. Removed
/// when the process exits normally.
inline const std::filesystem::path& ScratchDir() {
  struct Scratch {
    std::filesystem::path dir;
    Scratch() {
      std::error_code ec;
      const std::filesystem::path base = std::filesystem::is_directory("/dev/shm", ec)
                                             ? std::filesystem::path("/dev/shm")
                                             : std::filesystem::temp_directory_path();
      dir = base / ("aar-fuzz-" + std::to_string(::getpid()));
      std::filesystem::create_directories(dir);
    }
    ~Scratch() {
      std::error_code ec;
      std::filesystem::remove_all(dir, ec);
    }
  };
  static const Scratch scratch;
  return scratch.dir;
}

/// Writes the input to ScratchDir()/name and returns the path.
inline std::filesystem::path WriteInput(const uint8_t* data, size_t size, const std::string& name) {
  const std::filesystem::path path = ScratchDir() / name;
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return path;
}

inline std::string_view AsText(const uint8_t* data, size_t size) { return {reinterpret_cast<const char*>(data), size}; }

}  // namespace aar::fuzz
