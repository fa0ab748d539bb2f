#pragma once
// Helpers shared by the test executables: temporary folders, running the
// command-line tools, reading files.

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "aar/error.h"

namespace aar::test {

/// A fresh empty folder under the build tree, removed at destruction; named
/// after the running test unless a name is given.
class TempDir {
 public:
  explicit TempDir(const std::string& name = ::testing::UnitTest::GetInstance()->current_test_info()->name()) {
    path_ = std::filesystem::path(AAR_BINARY_DIR) / "test-tmp" / (name + "-" + std::to_string(::getpid()));
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~TempDir() { std::filesystem::remove_all(path_); }
  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::string& child) const { return path_ / child; }

 private:
  std::filesystem::path path_;
};

struct CommandResult {
  int exit_code = -1;
  std::string output;  ///< stdout and stderr together
};

/// Runs a shell command line, capturing its output and exit code.
inline CommandResult RunCommand(const std::string& command) {
  CommandResult result;
  FILE* pipe = ::popen((command + " 2>&1").c_str(), "r");
  if (pipe == nullptr) return result;
  std::array<char, 4096> buffer{};
  size_t n = 0;
  while ((n = std::fread(buffer.data(), 1, buffer.size(), pipe)) > 0) result.output.append(buffer.data(), n);
  const int status = ::pclose(pipe);
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

inline std::filesystem::path SourcePath(const std::string& relative) {
  return std::filesystem::path(AAR_SOURCE_DIR) / relative;
}

inline std::filesystem::path BinaryPath(const std::string& relative) {
  return std::filesystem::path(AAR_BINARY_DIR) / relative;
}

/// The rigs committed in scenes/, for tests instantiated over each of them.
inline const auto kCommittedRigs =
    ::testing::Values("scenes/rig.json", "scenes/rig-thesis.json", "scenes/rig-distorted.json", "scenes/rig-noisy.json",
                      "scenes/rig-rolling.json", "scenes/rig-1080p.json", "scenes/rig-2160p.json");

/// A parameterised test's name for a committed rig: its file stem, '-' as '_'.
inline std::string CommittedRigName(const ::testing::TestParamInfo<const char*>& info) {
  std::string name = std::filesystem::path(info.param).stem().string();
  std::replace(name.begin(), name.end(), '-', '_');
  return name;
}

/// The aar::Error message `call` throws ("" when it does not throw).
template <typename Call>
std::string ErrorOf(Call call) {
  try {
    call();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace aar::test
