#pragma once
// Which frames a run processes: an optional range `--frames a:b` (half open,
// either end may be omitted) and an optional shard `--shard K/N` (frames whose
// index i satisfies i % N == K). When no shard is given and the Slurm job-array
// variables SLURM_ARRAY_TASK_ID / SLURM_ARRAY_TASK_COUNT are set, they are used
// (task ids are taken relative to SLURM_ARRAY_TASK_MIN, default 0; an array
// that is not contiguous, per SLURM_ARRAY_TASK_MAX and _STEP, is refused).

#include <cstddef>
#include <string>
#include <vector>

namespace aar {

struct FrameSelection {
  size_t begin = 0;                      ///< first frame (inclusive)
  size_t end = static_cast<size_t>(-1);  ///< last frame (exclusive); -1 = to the end
  size_t shard_index = 0;                ///< K in K/N
  size_t shard_count = 1;                ///< N in K/N

  /// The selected frame indices among `frame_count`, ascending.
  std::vector<size_t> Select(size_t frame_count) const;
  /// Throws aar::Error prefixed by `what` (the dataset or flight path) when
  /// the range starts at or past `frame_count` (a range wholly past the end
  /// selects nothing; a shard may legitimately select nothing).
  void CheckWithin(size_t frame_count, const std::string& what) const;
  /// "-shardKofN" for a shard, "" otherwise (distinct default output folders).
  std::string ShardSuffix() const;
};

/// Parses `--frames` and `--shard` values (empty string = not given) and the
/// Slurm environment; throws aar::Error with the offending text.
FrameSelection ParseFrameSelection(const std::string& frames, const std::string& shard);

}  // namespace aar
