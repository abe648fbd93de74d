// Internal to softpbr_golden: the per-sample difference compare() and diff_image() share,
// and the check that an image's pixel data matches its size.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>

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

// Throws std::invalid_argument("<what>: ...") unless rgba holds width × height × 4 samples.
template <class Image>
void check_pixel_data(const Image& image, const std::string& what) {
  if (image.width < 0 || image.height < 0 ||
      image.rgba.size() != static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height) * 4)
    throw std::invalid_argument(what + ": image size " + std::to_string(image.width) + "x" +
                                std::to_string(image.height) + " and pixel data (" + std::to_string(image.rgba.size()) +
                                " samples) disagree");
}

}  // namespace softpbr::golden::detail
