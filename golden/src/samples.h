// Internal to softpbr_golden: the per-sample difference compare() and diff_image() share.
// (The check that an image's pixel data matches its size is image::check_pixels.)
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

namespace softpbr::golden::detail {

// |expected − actual| of one sample in the image's units.
inline double sample_diff(std::uint8_t e, std::uint8_t a) { return e > a ? e - a : a - e; }

// Floats: 0 when the values are equal or the bits are (the same NaN); a NaN against
// anything else is +inf; otherwise the difference, exact in double.
inline double sample_diff(float e, float a) {
  if (e == a) return 0.0;
  std::uint32_t be, ba;
  std::memcpy(&be, &e, 4);
  std::memcpy(&ba, &a, 4);
  if (be == ba) return 0.0;
  if (std::isnan(e) || std::isnan(a)) return std::numeric_limits<double>::infinity();
  return std::fabs(static_cast<double>(e) - static_cast<double>(a));
}

}  // namespace softpbr::golden::detail
