// softpbr/golden/compare.h — comparing two images: an exact content hash, difference
// statistics, a heat-map diff image and a side-by-side image.
//
// Differences are measured per channel in the images' own units: 8-bit code values
// (0–255) for Image8, float values for ImageF and Target. The peak value for PSNR is
// 255 for Image8 and 1 for float images.
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include "softpbr/golden/image.h"
#include "softpbr/raster/target.h"

namespace softpbr::golden {

// ---- Content hash ------------------------------------------------------------------------
// 64-bit FNV-1a (offset basis 0xcbf29ce484222325, prime 0x100000001b3: for each byte b,
// h = (h XOR b) × prime mod 2^64) over this byte sequence:
//   width, height, channel count (4), bytes per channel (1 for Image8, 4 for float) —
//     each as an unsigned 32-bit integer, little-endian;
//   then the samples, rows from the top, pixels left to right, channels R, G, B, A:
//     Image8: one byte per sample; float: the IEEE-754 binary32 bits of each sample,
//     little-endian.
// Equal hashes mean equal size and bit-identical pixels; the value is the same on every
// platform. Example: a 1×1 Image8 with RGBA (255, 0, 0, 255) hashes to 0xc9fea42538ede09e.
// (raster::hash_colors, used by the project's .hash render goldens, is another hash:
// XXH3-64 over the float bits alone, without the 16 header bytes.)
std::uint64_t content_hash(const Image8& image);
std::uint64_t content_hash(const ImageF& image);
std::uint64_t content_hash(const raster::Target& target);  // = content_hash(to_image(target))

// A hash as 16 lowercase hexadecimal digits, as .hash files hold it.
std::string hash_hex(std::uint64_t hash);

// ---- Statistics ---------------------------------------------------------------------------
struct Comparison {
  int expected_width = 0, expected_height = 0;
  int actual_width = 0, actual_height = 0;
  // The statistics below are computed only when the sizes match (else they stay 0).
  bool identical = false;                  // same size and every sample equal
  std::array<double, 4> max_abs_diff{};    // per channel R, G, B, A: max |expected − actual|
  std::array<double, 4> mean_abs_diff{};   // per channel: mean |expected − actual|
  double mean_abs_diff_all = 0;            // mean over every sample
  double rmse = 0;                         // sqrt(mean over every sample of diff²)
  double psnr = 0;                         // 20·log10(peak / rmse) dB; +inf when identical
  double peak = 0;                         // 255 (Image8) or 1 (float)
  double threshold = 0;                    // as passed to compare()
  std::uint64_t pixels = 0;                // width × height
  std::uint64_t pixels_above = 0;          // pixels whose largest channel diff > threshold
  double fraction_above = 0;               // pixels_above / pixels

  bool same_size() const { return expected_width == actual_width && expected_height == actual_height; }
  double max_diff() const;                 // largest of max_abs_diff
  // One paragraph: the size mismatch (both sizes), or every statistic above.
  std::string describe() const;
};

// Compares expected with actual. Float samples are equal when their values are equal or
// their bits are (the same NaN); a NaN against anything else differs by +inf. Throws
// std::invalid_argument when an image's pixel data does not match its size. Different
// sizes are not an error: the result says so (same_size() is false).
Comparison compare(const Image8& expected, const Image8& actual, double threshold = 0);
Comparison compare(const ImageF& expected, const ImageF& actual, double threshold = 0);
Comparison compare(const raster::Target& expected, const raster::Target& actual, double threshold = 0);

// ---- Images to look at ---------------------------------------------------------------------
// A heat map of the difference, one pixel per pixel, opaque: black where the pixels are
// equal; elsewhere d = largest channel |diff| picks a colour on the ramp
// black (s = 0) → red (1/3) → yellow (2/3) → white (1) at s = 1/3 + 2/3 · min(d / scale, 1),
// so the smallest difference is still clearly red. scale = 0 uses the largest finite d of
// the image (it shows white); infinite differences (NaN against a number) show white.
// Throws std::invalid_argument naming both sizes when they differ.
Image8 diff_image(const Image8& expected, const Image8& actual, double scale = 0);
Image8 diff_image(const ImageF& expected, const ImageF& actual, double scale = 0);
Image8 diff_image(const raster::Target& expected, const raster::Target& actual, double scale = 0);

// expected | actual | diff_image, left to right, 3·width × height. Float images are shown
// through to_srgb8. When the sizes differ: expected | actual only, each at the top left of
// its own column, the rest opaque black (width = sum of widths, height = the larger).
Image8 side_by_side(const Image8& expected, const Image8& actual, double scale = 0);
Image8 side_by_side(const ImageF& expected, const ImageF& actual, double scale = 0);
Image8 side_by_side(const raster::Target& expected, const raster::Target& actual, double scale = 0);

}  // namespace softpbr::golden
