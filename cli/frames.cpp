// Frame lists, shards and output patterns (see frames.h).
#include "frames.h"

#include <charconv>
#include <cstdio>

#include "cli_error.h"

namespace softpbr::cli {

namespace {
bool parse_long(std::string_view s, long& out) {
  if (s.empty()) return false;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
  return ec == std::errc() && end == s.data() + s.size();
}
}  // namespace

FrameRange parse_frames(const std::string& text) {
  const std::string expected = "--frames: expected A..B or A with 0 <= A <= B <= " + std::to_string(kMaxFrame) + ", got \"" + text + "\"";
  FrameRange r;
  const auto dots = text.find("..");
  const bool ok = dots == std::string::npos
                      ? parse_long(text, r.first) && (r.last = r.first, true)
                      : parse_long(std::string_view(text).substr(0, dots), r.first) &&
                            parse_long(std::string_view(text).substr(dots + 2), r.last);
  if (!ok || r.first < 0 || r.last < r.first || r.last > kMaxFrame) throw Error(kExitUsage, expected);
  return r;
}

Shard parse_shard(const std::string& text) {
  Shard s;
  const auto slash = text.find('/');
  const bool ok = slash != std::string::npos && parse_long(std::string_view(text).substr(0, slash), s.index) &&
                  parse_long(std::string_view(text).substr(slash + 1), s.count) && s.count >= 1 &&
                  s.index >= 0 && s.index < s.count;
  if (!ok) throw Error(kExitUsage, "--shard: expected i/N with 0 <= i < N (i counts from 0), got \"" + text + "\"");
  return s;
}

long shard_frame_count(const FrameRange& range, const Shard& shard) {
  // frames <= kMaxFrame + 1 and 0 <= index < count: no sum here can overflow, whatever
  // the count (--shard 0/9223372036854775807 is one frame, frame A).
  const long frames = range.last - range.first + 1;
  return frames > shard.index ? (frames - shard.index - 1) / shard.count + 1 : 0;
}

bool has_frame_pattern(const std::string& pattern) {
  const auto first = pattern.find('#');
  if (first == std::string::npos) return false;
  const auto end = pattern.find_first_not_of('#', first);
  if (end != std::string::npos && pattern.find('#', end) != std::string::npos)
    throw Error(kExitUsage, pattern + ": an output name may have one run of '#' (the frame number), not several");
  return true;
}

std::string frame_path(const std::string& pattern, long frame) {
  const auto first = pattern.find('#');
  if (first == std::string::npos) return pattern;
  auto end = pattern.find_first_not_of('#', first);
  if (end == std::string::npos) end = pattern.size();
  char digits[32];
  std::snprintf(digits, sizeof digits, "%0*ld", static_cast<int>(end - first), frame);
  return pattern.substr(0, first) + digits + pattern.substr(end);
}

}  // namespace softpbr::cli
