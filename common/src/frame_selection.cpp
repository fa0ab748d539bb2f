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

void FrameSelection::CheckWithin(size_t frame_count, const std::string& what) const {
  if (begin >= frame_count) {
    throw Error(what + ": --frames starts at " + std::to_string(begin) + ", past the last frame (" +
                std::to_string(frame_count) + " frames, 0 to " + std::to_string(frame_count - 1) + ")");
  }
}

std::string FrameSelection::ShardSuffix() const {
  if (shard_count <= 1) return "";
  return "-shard" + std::to_string(shard_index) + "of" + std::to_string(shard_count);
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
      const char* max = std::getenv("SLURM_ARRAY_TASK_MAX");
      const char* step = std::getenv("SLURM_ARRAY_TASK_STEP");
      const long long first = min != nullptr ? ParseInteger(min, "SLURM_ARRAY_TASK_MIN") : 0;
      const long long n = ParseInteger(count, "SLURM_ARRAY_TASK_COUNT");
      // Shards are ID - MIN of COUNT: only a contiguous array (--array=A-B, step 1) covers every frame once.
      const bool contiguous = (step == nullptr || ParseInteger(step, "SLURM_ARRAY_TASK_STEP") == 1) &&
                              (max == nullptr || ParseInteger(max, "SLURM_ARRAY_TASK_MAX") - first + 1 == n);
      if (!contiguous) {
        throw Error(std::string("Slurm array is not contiguous (SLURM_ARRAY_TASK_MIN ") + (min ? min : "unset") +
                    ", MAX " + (max ? max : "unset") + ", COUNT " + count + ", STEP " + (step ? step : "unset") +
                    "): submit --array=0-" + std::to_string(n > 0 ? n - 1 : 0) + " or pass --shard K/N");
      }
      const long long k = ParseInteger(id, "SLURM_ARRAY_TASK_ID") - first;
      if (k < 0) throw Error("SLURM_ARRAY_TASK_ID is below SLURM_ARRAY_TASK_MIN");
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
