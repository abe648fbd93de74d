// softpbr/raster/color.h — exact, deterministic linear → sRGB encoding to 8 bits.
//
// The sRGB transfer function (IEC 61966-2-1) needs x^(1/2.4), a libm pow whose last bit may
// differ between platforms. Encoding to 8 bits needs only the 255 linear values where the
// code changes: threshold k is the linear value whose sRGB encoding is (k + 0.5) / 255.
// They are computed at compile time from the decoding function with basic operations only,
// so the code of a pixel is the number of thresholds at or below it: exact, and the same
// bits everywhere.
#pragma once

#include <array>
#include <cstdint>

namespace softpbr::raster {

// The 255 linear thresholds, ascending. Threshold k separates codes k and k + 1.
const std::array<float, 255>& srgb8_thresholds();

// Linear value in [0, 1] → 8-bit sRGB code (NaN and negatives → 0, above 1 → 255).
std::uint8_t linear_to_srgb8(float linear);

// The exact sRGB decoding function in double (code/255 → linear), for tests and tables.
double srgb_to_linear(double encoded);

// Linear alpha or data channel → 8 bits by rounding to nearest (NaN → 0, clamped).
std::uint8_t unorm8(float value);

}  // namespace softpbr::raster
