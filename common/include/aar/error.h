#pragma once
// One exception type for every user-facing failure. The message names the
// file (and line or frame when known) and the reason; executables catch it at
// the top, print one line and exit non-zero.

#include <filesystem>
#include <stdexcept>
#include <string>

namespace aar {

/// `text` with every control byte (a NUL, a newline, ...) written as \xHH, so
/// that a message quoting a file's bytes stays whole and on one line.
inline std::string OneLine(const std::string& text) {
  static const char* kHex = "0123456789ABCDEF";
  std::string line;
  line.reserve(text.size());
  for (const char c : text) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte < 0x20 || byte == 0x7f) {
      line += "\\x";
      line += kHex[byte >> 4];
      line += kHex[byte & 15];
    } else {
      line += c;
    }
  }
  return line;
}

class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message) : std::runtime_error(OneLine(message)) {}
};

/// The one-line message of a failed std::filesystem call that reached the top
/// (a name too long, a loop of symbolic links, no permission): the path(s)
/// and the reason. Executables report it as refused input, exit 1.
inline std::string FileSystemMessage(const std::filesystem::filesystem_error& e) {
  std::string where = e.path1().string();
  if (!e.path2().empty()) where += " -> " + e.path2().string();
  return OneLine((where.empty() ? std::string("file system") : where) + ": " + e.code().message());
}

}  // namespace aar
