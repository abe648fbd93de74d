// frames.h — frame lists for batch rendering: "--frames A..B", "--shard i/N" and output
// patterns like out_####.png.
#pragma once

#include <string>
#include <vector>

#include "softpbr/job/render_job.h"

namespace softpbr::cli {

// The largest frame number (job::kMaxFrame, Python's too).
inline constexpr long kMaxFrame = job::kMaxFrame;

struct FrameRange {
  long first = 0;
  long last = 0;  // inclusive
};

struct Shard {
  long index = 0;  // 0-based, as Slurm's SLURM_ARRAY_TASK_ID and Kubernetes' JOB_COMPLETION_INDEX
  long count = 1;
};

// "A..B" (A <= B) or "A". Throws Error(kExitUsage) naming --frames.
FrameRange parse_frames(const std::string& text);
// "i/N" with 0 <= i < N. Throws Error(kExitUsage) naming --shard.
Shard parse_shard(const std::string& text);

// The frames of `range` a shard renders: the k-th frame of the range (k = 0, 1, …) belongs
// to shard k mod N, so every frame belongs to exactly one shard. Shard i renders
// shard_frame(range, shard, j) for j = 0 … shard_frame_count(range, shard) − 1.
long shard_frame_count(const FrameRange& range, const Shard& shard);
inline long shard_frame(const FrameRange& range, const Shard& shard, long j) {
  return range.first + shard.index + j * shard.count;
}

// Whether `pattern` has a run of '#' (exactly one is allowed; more throws Error(kExitUsage)).
bool has_frame_pattern(const std::string& pattern);
// The pattern with its run of n '#' replaced by the frame number zero-padded to n digits
// (more digits when the number needs them); a pattern without '#' is returned as is.
std::string frame_path(const std::string& pattern, long frame);

}  // namespace softpbr::cli
