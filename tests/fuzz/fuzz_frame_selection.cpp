// libFuzzer harness: --frames / --shard and the Slurm array variables
// (common/frame_selection.h). Input lines: --frames, --shard,
// SLURM_ARRAY_TASK_ID, _COUNT, _MIN, _MAX, _STEP (a missing line: unset).
#include <cstdlib>
#include <string>
#include <vector>

#include "aar/error.h"
#include "aar/frame_selection.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::vector<std::string> lines;
  std::string_view text = aar::fuzz::AsText(data, size);
  while (!text.empty() && lines.size() < 7) {
    const size_t newline = text.find('\n');
    lines.emplace_back(text.substr(0, newline));
    text.remove_prefix(newline == std::string_view::npos ? text.size() : newline + 1);
  }
  lines.resize(7);
  const char* variables[] = {"SLURM_ARRAY_TASK_ID", "SLURM_ARRAY_TASK_COUNT", "SLURM_ARRAY_TASK_MIN",
                             "SLURM_ARRAY_TASK_MAX", "SLURM_ARRAY_TASK_STEP"};
  for (size_t i = 0; i < 5; ++i) {
    const std::string& value = lines[2 + i];
    if (value.empty() || value.find('\0') != std::string::npos) {
      ::unsetenv(variables[i]);
    } else {
      ::setenv(variables[i], value.c_str(), 1);
    }
  }
  try {
    const aar::FrameSelection selection = aar::ParseFrameSelection(lines[0], lines[1]);
    selection.CheckWithin(609, "fuzz");
    const std::vector<size_t> frames = selection.Select(609);
    for (size_t i : frames) {
      if (i >= 609 || i < selection.begin || i % selection.shard_count != selection.shard_index) std::abort();
    }
    selection.ShardSuffix();
  } catch (const aar::Error&) {
  }
  return 0;
}
