#include "aar/frame_selection.h"

#include <algorithm>
#include <cstdlib>

#include "aar/error.h"
#include "aar/text.h"

namespace aar {

std::vector<size_t> FrameSelection::Select(size_t frame_count) const {
  std::vector<size_t> frames;
  for (size_t i = begin; i < std::min(end, frame_count); ++i) {
    if (i % shard_count == shard_index) frames.push_back(i);
  }
  return frames;
}

FrameSelection ParseFrameSelection(const std::string& frames, const std::string& shard) {
  FrameSelection selection;
  if (!frames.empty()) {
    const size_t colon = frames.find(':');
    if (colon == std::string::npos) throw Error("--frames '" + frames + "': expected a:b (e.g. 0:100, 50:, :10)");
    const std::string a = frames.substr(0, colon);
    const std::string b = frames.substr(colon + 1);
    if (!a.empty()) selection.begin = static_cast<size_t>(ParseInteger(a, "--frames"));
    if (!b.empty()) selection.end = static_cast<size_t>(ParseInteger(b, "--frames"));
    if (selection.end <= selection.begin) throw Error("--frames '" + frames + "': empty range");
  }
  std::string shard_text = shard;
  if (shard_text.empty()) {
    const char* id = std::getenv("SLURM_ARRAY_TASK_ID");
    const char* count = std::getenv("SLURM_ARRAY_TASK_COUNT");
    if (id != nullptr && count != nullptr) {
      const char* min = std::getenv("SLURM_ARRAY_TASK_MIN");
      const long long k =
          ParseInteger(id, "SLURM_ARRAY_TASK_ID") - (min != nullptr ? ParseInteger(min, "SLURM_ARRAY_TASK_MIN") : 0);
      shard_text = std::to_string(k) + "/" + count;
    }
  }
  if (!shard_text.empty()) {
    const size_t slash = shard_text.find('/');
    if (slash == std::string::npos) throw Error("--shard '" + shard_text + "': expected K/N (e.g. 0/4)");
    selection.shard_index = static_cast<size_t>(ParseInteger(shard_text.substr(0, slash), "--shard K"));
    selection.shard_count = static_cast<size_t>(ParseInteger(shard_text.substr(slash + 1), "--shard N"));
    if (selection.shard_count == 0 || selection.shard_index >= selection.shard_count) {
      throw Error("--shard '" + shard_text + "': need 0 <= K < N");
    }
  }
  return selection;
}

}  // namespace aar
