#pragma once
// Helpers of the end-to-end tests (test_pipeline): the shared rendered
// datasets, running aar-render / aar-analyze, and comparing run outputs
// without their timing fields.
//
// CTest runs every test of a GoogleTest executable in its own process
// (gtest_discover_tests), so a GoogleTest Environment alone would render once
// per test. The datasets are therefore rendered once into a cache under the
// build tree (build/test-cache/pipeline/), keyed by the SHA-256 of the
// aar-render executable, of its scene inputs and of the flight path, and
// re-used by every later test process; a file lock serialises concurrent
// test processes (ctest --parallel). Tests only read the cached datasets and
// copy them when they must corrupt something.

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "../test_support.h"

namespace aar::test {

/// The datasets shared by the pipeline tests (read-only).
struct PipelineDatasets {
  /// Calibration pairs (x16, 12 pairs) and kNearContactFrames frames of
  /// flightpaths/conops.csv near the contact position (x16, region C).
  std::filesystem::path near_contact;
  /// Two frames at x1, no calibration pairs: frame 0 at the contact position,
  /// frame 1 with the receiver 200 m in front of the tanker (out of view).
  std::filesystem::path out_of_view;
  std::string error;  ///< non-empty when rendering failed (the output of the failing command)
};

/// Frames of the near-contact dataset: conops.csv frames 590 to 597.
inline constexpr size_t kNearContactFrames = 8;

/// Renders the datasets on first use in this build tree (a few seconds on
/// lavapipe), afterwards returns the cached ones.
const PipelineDatasets& SharedDatasets();

/// Fails the current test when the shared datasets could not be rendered.
#define ASSERT_DATASETS() \
  ASSERT_TRUE(::aar::test::SharedDatasets().error.empty()) << ::aar::test::SharedDatasets().error

/// Paths of the executables under test.
std::filesystem::path RenderExe();
std::filesystem::path AnalyzeExe();

/// A path or word quoted for /bin/sh.
std::string Quote(const std::string& text);
inline std::string Quote(const std::filesystem::path& path) { return Quote(path.string()); }

/// Runs aar-analyze with `arguments` (already quoted), without Slurm array
/// variables that would shard the run implicitly.
CommandResult RunAnalyze(const std::string& arguments);

/// Copies a dataset folder (recursively) to `to`, which must not exist.
void CopyDataset(const std::filesystem::path& from, const std::filesystem::path& to);

/// Lines of a frames.csv without the timing columns: each line cut to the
/// header's leading fields that do not start with "ms_". Fails the current
/// test when a non-timing column follows a timing column.
std::vector<std::string> FramesCsvWithoutTiming(const std::filesystem::path& frames_csv);

/// summary.json without its "timing" object.
nlohmann::json SummaryWithoutTiming(const std::filesystem::path& summary_json);

/// Number of lines of `text` (newline characters, plus one for an unterminated last line).
size_t CountLines(const std::string& text);

}  // namespace aar::test
