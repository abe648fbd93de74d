// softpbr/golden/golden.h — checking an image against a golden file: exact by default,
// with optional tolerances; on failure the actual, diff and side-by-side images are
// written for looking; in update mode goldens are rewritten instead. The doctest macros
// in softpbr/golden/doctest_checks.h are thin wrappers around match_golden and match_render.
//
// Golden formats, by extension:
//   .png — 8-bit. A float image or Target is first encoded with to_srgb8 (exact sRGB,
//          clamped), so the check covers what the PNG can hold.
//   .hdr — float (Radiance RGBE). A float image or Target goes through hdr_round_trip
//          first; an Image8 cannot be checked against an .hdr golden.
//   NAME.hash + NAME.png (match_render) — a render: the float colour buffer's
//          raster::hash_colors as 16 hex digits, and the displayed 8-bit image.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "softpbr/golden/compare.h"
#include "softpbr/golden/image.h"
#include "softpbr/raster/target.h"

namespace softpbr::golden {

// How far an image may be from its golden. A pixel differs when one of its channels
// differs by more than max_diff (in the image's units: 8-bit codes for PNG goldens, float
// values for .hdr goldens); the check passes when at most max_pixels pixels differ and the
// sizes are equal. The default {0, 0} is exact: every sample equal.
struct Tolerance {
  double max_diff = 0;
  std::uint64_t max_pixels = 0;
};

struct Options {
  std::filesystem::path golden_dir;   // relative golden paths resolve here (empty: the working directory)
  std::filesystem::path output_dir;   // failure images go here (empty: ./golden-output)
  bool update = false;                // rewrite goldens that fail (or are missing) instead of failing
  std::string update_command = "SOFTPBR_UPDATE_GOLDENS=1 ctest";  // named in failure messages
};

// `defaults` overridden by the environment:
//   SOFTPBR_GOLDEN_DIR=path     → golden_dir
//   SOFTPBR_GOLDEN_OUTPUT=path  → output_dir
//   SOFTPBR_UPDATE_GOLDENS=1    → update (any other value, or unset: no update)
Options options_from_environment(Options defaults = {});

struct MatchResult {
  bool passed = false;
  bool updated = false;                        // update mode wrote the golden (passed is true)
  std::filesystem::path golden;                // the resolved golden path (NAME.hash for renders)
  Comparison comparison;                       // of the 8-bit or float images; zero if not compared
  std::vector<std::filesystem::path> written;  // failure images written (actual, diff, side by side)
  std::string message;                         // what happened, statistics, paths, how to update
};

// Checks `actual` against the golden file at `golden` (relative paths resolve against
// options.golden_dir). Never throws for a missing, unreadable or different golden: the
// result says what went wrong. On failure writes, under options.output_dir/<golden's
// relative folder>/: STEM.actual.png (or .hdr), and when the sizes match STEM.diff.png;
// always STEM.side-by-side.png when the golden could be read. In update mode a golden
// that is missing or outside the tolerance is rewritten (atomically) and the check passes;
// one inside the tolerance is left as it is.
MatchResult match_golden(const Image8& actual, const std::filesystem::path& golden,
                         const Tolerance& tolerance = {}, const Options& options = options_from_environment());
MatchResult match_golden(const ImageF& actual, const std::filesystem::path& golden,
                         const Tolerance& tolerance = {}, const Options& options = options_from_environment());
MatchResult match_golden(const raster::Target& actual, const std::filesystem::path& golden,
                         const Tolerance& tolerance = {}, const Options& options = options_from_environment());

// Checks a render bit for bit: raster::hash_colors(target) against golden_stem + ".hash"
// (16 hex digits), and `image` (the target as displayed, e.g. tone mapped) against
// golden_stem + ".png", both exactly. Any bit difference in the float colour buffer fails,
// even one too small to change the PNG. On failure writes STEM.actual.png,
// STEM.actual.hash, STEM.diff.png and STEM.side-by-side.png (as match_golden); in update
// mode rewrites whichever of the two files differs.
MatchResult match_render(const raster::Target& target, const Image8& image, const std::filesystem::path& golden_stem,
                         const Options& options = options_from_environment());

}  // namespace softpbr::golden
