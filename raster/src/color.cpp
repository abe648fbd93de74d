// Exact linear → sRGB encoding to 8 bits through compile-time thresholds (see color.h).
#include "softpbr/raster/color.h"

#include <algorithm>
#include <bit>
#include <cstddef>

namespace softpbr::raster {

namespace {

// x^(1/5) by Newton's method in double, from above: y ← y − (y⁵ − x)/(5y⁴) decreases
// monotonically to the root, so the loop ends when it stops decreasing. Basic operations
// only, so constexpr-evaluable and identical everywhere.
constexpr double fifth_root(double x) {
  if (x <= 0.0) return 0.0;
  double y = x > 1.0 ? x : 1.0;
  for (int i = 0; i < 200; ++i) {
    const double y2 = y * y;
    const double y4 = y2 * y2;
    const double next = y - (y4 * y - x) / (5.0 * y4);
    if (!(next < y)) break;
    y = next;
  }
  return y;
}

// The sRGB decoding curve (IEC 61966-2-1): e ≤ 0.04045 → e / 12.92, else ((e + 0.055) / 1.055)^2.4,
// with x^2.4 = x² · (x^(1/5))².
constexpr double decode(double e) {
  if (e <= 0.04045) return e / 12.92;
  const double x = (e + 0.055) / 1.055;
  const double r = fifth_root(x);
  return x * x * (r * r);
}

constexpr std::array<float, 255> make_thresholds() {
  std::array<float, 255> t{};
  for (int k = 0; k < 255; ++k) t[k] = static_cast<float>(decode((k + 0.5) / 255.0));
  return t;
}

constexpr std::array<float, 255> kThresholds = make_thresholds();
static_assert(kThresholds[0] > 0.0f && kThresholds[254] < 1.0f);

}  // namespace

const std::array<float, 255>& srgb8_thresholds() { return kThresholds; }

double srgb_to_linear(double encoded) { return decode(encoded); }

namespace {

// Positive floats order as their bits, so key k = bits >> 16 holds the values from
// float(k << 16) up to the next key's start; kFirst[k] counts the thresholds below that
// start. Keys up to that of 1.0f cover [0, 1].
constexpr std::uint32_t kLastKey = 0x3f800000u >> 16;

constexpr std::array<std::uint8_t, kLastKey + 1> make_first() {
  std::array<std::uint8_t, kLastKey + 1> first{};
  std::size_t below = 0;
  for (std::uint32_t k = 0; k <= kLastKey; ++k) {
    const float start = std::bit_cast<float>(k << 16);
    while (below < kThresholds.size() && kThresholds[below] < start) ++below;
    first[k] = static_cast<std::uint8_t>(below);
  }
  return first;
}

constexpr std::array<std::uint8_t, kLastKey + 1> kFirst = make_first();

}  // namespace

std::uint8_t linear_to_srgb8(float linear) {
  // The code is the number of thresholds at or below the value (NaN compares false → 0).
  if (!(linear >= kThresholds[0])) return 0;
  if (!(linear < 1.0f)) return 255;  // every threshold is below 1
  // The thresholds below the value's key, then the few inside it (at most two: a key spans
  // under 1% of its value, the codes' steps are wider): the same count as a binary search.
  unsigned k = kFirst[std::bit_cast<std::uint32_t>(linear) >> 16];
  while (k < kThresholds.size() && kThresholds[k] <= linear) ++k;
  return static_cast<std::uint8_t>(k);
}

std::uint8_t unorm8(float value) {
  if (!(value > 0.0f)) return 0;  // NaN, negatives
  if (value >= 1.0f) return 255;
  return static_cast<std::uint8_t>(value * 255.0f + 0.5f);
}

}  // namespace softpbr::raster
