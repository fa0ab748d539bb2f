#include "pipeline_support.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "aar/dataset.h"
#include "aar/error.h"
#include "aar/file_io.h"

namespace aar::test {
namespace {

namespace fs = std::filesystem;

// Strips the variables that make both executables shard implicitly.
const char* const kNoSlurm = "env -u SLURM_ARRAY_TASK_ID -u SLURM_ARRAY_TASK_COUNT -u SLURM_ARRAY_TASK_MIN ";

fs::path CacheRoot() { return BinaryPath("test-cache/pipeline"); }

/// Exclusive lock on a file, held for the object's lifetime (other test
/// processes of a parallel ctest wait for the rendering to finish).
class FileLock {
 public:
  explicit FileLock(const fs::path& path) : fd_(::open(path.c_str(), O_CREAT | O_RDWR | O_CLOEXEC, 0644)) {
    if (fd_ < 0 || ::flock(fd_, LOCK_EX) != 0) throw Error(path.string() + ": cannot lock the test cache");
  }
  ~FileLock() {
    if (fd_ >= 0) ::close(fd_);  // closing releases the lock
  }
  FileLock(const FileLock&) = delete;
  FileLock& operator=(const FileLock&) = delete;

 private:
  int fd_;
};

struct DatasetRecipe {
  std::string name;
  std::string flight_path_csv;  ///< content
  int msaa = 16;
  bool calib = false;  ///< also render the thesis's 12 calibration pairs (--far-boards none)
  bool depth = false;  ///< also render depth truth, object ids and silhouettes of both cameras
};

// The near-contact CSV: conops.csv frames 590 .. 590 + kNearContactFrames - 1 (region C, ~32 m).
std::string NearContactCsv() {
  std::ifstream in(SourcePath("flightpaths/conops.csv"));
  std::string line, csv;
  for (size_t number = 0; std::getline(in, line); ++number) {
    // Line 0 is the header; frame i is line i + 1 (0-based).
    if (number == 0 || (number >= 591 && number < 591 + kNearContactFrames)) csv += line + "\n";
  }
  return csv;
}

std::string CacheKey(const DatasetRecipe& recipe) {
  std::ostringstream key;
  key << "aar-render " << Sha256File(RenderExe()) << "\n";
  for (const char* scene : {"scenes/rig.json", "scenes/c12.glb", "scenes/kc46.glb", "scenes/calib_board.glb"}) {
    key << scene << " " << Sha256File(SourcePath(scene)) << "\n";
  }
  const char* icd = std::getenv("VK_ICD_FILENAMES");
  key << "VK_ICD_FILENAMES " << (icd != nullptr ? icd : "") << "\n";
  key << "msaa " << recipe.msaa << " calib " << recipe.calib << " depth " << recipe.depth << "\n"
      << recipe.flight_path_csv;
  return Sha256Hex(key.str());
}

// True when `dir` is a complete dataset whose every listed file has its hash.
bool DatasetIntact(const fs::path& dir) {
  try {
    const Manifest manifest = ReadManifest(dir);
    if (!manifest.complete) return false;
    for (const auto& [path, hash] : manifest.files) {
      if (!fs::is_regular_file(dir / path) || Sha256File(dir / path) != hash) return false;
    }
    return true;
  } catch (const Error&) {
    return false;
  }
}

// Renders `recipe` into the cache unless an intact copy with the same key is
// there; returns "" or the failing command's output.
std::string EnsureDataset(const DatasetRecipe& recipe, fs::path* dir_out) {
  const fs::path dir = CacheRoot() / recipe.name;
  const fs::path key_file = CacheRoot() / (recipe.name + ".key");
  *dir_out = dir;
  const std::string key = CacheKey(recipe);
  if (fs::is_regular_file(key_file) && ReadFileBytes(key_file) == key && DatasetIntact(dir)) return "";

  fs::remove(key_file);
  fs::remove_all(dir);
  const fs::path csv = CacheRoot() / (recipe.name + ".csv");
  WriteFileAtomic(csv, recipe.flight_path_csv);
  const std::string common =
      " --no-progress --msaa " + std::to_string(recipe.msaa) + " --rig " + Quote(SourcePath("scenes/rig.json"));
  std::vector<std::string> commands;
  if (recipe.calib) {
    commands.push_back("calib " + Quote(dir) + common + " --far-boards none --board " +
                       Quote(SourcePath("scenes/calib_board.glb")));
  }
  commands.push_back("render " + Quote(dir) + common + " --receiver " + Quote(SourcePath("scenes/c12.glb")) +
                     " --tanker " + Quote(SourcePath("scenes/kc46.glb")) + " --flight-path " + Quote(csv) +
                     (recipe.depth ? " --depth-right" : ""));
  for (const std::string& arguments : commands) {
    const std::string command = kNoSlurm + Quote(RenderExe()) + " " + arguments;
    const CommandResult result = RunCommand(command);
    if (result.exit_code != 0) {
      return command + "\nexit code " + std::to_string(result.exit_code) + ":\n" + result.output;
    }
  }
  if (!DatasetIntact(dir)) return dir.string() + ": rendered dataset is incomplete";
  WriteFileAtomic(key_file, key);
  return "";
}

PipelineDatasets RenderSharedDatasets() {
  PipelineDatasets datasets;
  try {
    fs::create_directories(CacheRoot());
    const FileLock lock(CacheRoot() / "lock");
    datasets.error = EnsureDataset({"near-contact-x16", NearContactCsv(), 16, true, true}, &datasets.near_contact);
    if (datasets.error.empty()) {
      const std::string csv =
          "time_s,x_m,y_m,z_m,roll_deg,pitch_deg,yaw_deg\n"
          "0.0,-47.7284,-0.0017,-18.9048,1.6603,1.2382,-1.0275\n"
          "0.5,200.0,0.0,-18.9,0.0,0.0,0.0\n";
      datasets.error = EnsureDataset({"out-of-view-x1", csv, 1, false}, &datasets.out_of_view);
    }
  } catch (const std::exception& e) {
    datasets.error = e.what();
  }
  return datasets;
}

}  // namespace

const PipelineDatasets& SharedDatasets() {
  static const PipelineDatasets datasets = RenderSharedDatasets();
  return datasets;
}

fs::path RenderExe() { return BinaryPath("renderer/aar-render"); }
fs::path AnalyzeExe() { return BinaryPath("analyzer/aar-analyze"); }

std::string Quote(const std::string& text) {
  std::string quoted = "'";
  for (char c : text) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

CommandResult RunAnalyze(const std::string& arguments) {
  return RunCommand(kNoSlurm + Quote(AnalyzeExe()) + " " + arguments);
}

void CopyDataset(const fs::path& from, const fs::path& to) {
  fs::create_directories(to.parent_path());
  fs::copy(from, to, fs::copy_options::recursive);
}

std::vector<std::string> FramesCsvWithoutTiming(const fs::path& frames_csv) {
  std::istringstream in(ReadFileBytes(frames_csv));
  std::vector<std::string> lines;
  std::string line;
  size_t keep = 0;
  for (bool header = true; std::getline(in, line); header = false) {
    std::vector<std::string> fields;
    std::istringstream fields_in(line);
    for (std::string field; std::getline(fields_in, field, ',');) fields.push_back(field);
    if (header) {
      while (keep < fields.size() && fields[keep].rfind("ms_", 0) != 0) ++keep;
      for (size_t i = keep; i < fields.size(); ++i) {
        EXPECT_EQ(fields[i].rfind("ms_", 0), 0u) << frames_csv << ": column " << fields[i] << " after timing columns";
      }
      EXPECT_GT(keep, 0u) << frames_csv;
      EXPECT_LT(keep, fields.size()) << frames_csv << ": no ms_* columns";
    }
    std::string cut;
    for (size_t i = 0; i < std::min(keep, fields.size()); ++i) cut += (i ? "," : "") + fields[i];
    lines.push_back(cut);
  }
  return lines;
}

nlohmann::json SummaryWithoutTiming(const fs::path& summary_json) {
  nlohmann::json summary = ReadJsonFile(summary_json);
  EXPECT_TRUE(summary.contains("timing")) << summary_json;
  summary.erase("timing");
  return summary;
}

size_t CountLines(const std::string& text) {
  size_t lines = static_cast<size_t>(std::count(text.begin(), text.end(), '\n'));
  if (!text.empty() && text.back() != '\n') ++lines;
  return lines;
}

}  // namespace aar::test
