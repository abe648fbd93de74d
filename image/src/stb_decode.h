// Internal to softpbr_image: the calls into stb_image that jpeg.cpp and hdr.cpp share,
// each run after the file's own checks, and stb_image_write's RGBE encoder. stb_decode.cpp
// is the one file that includes stb's headers (their implementations are static there).
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string_view>
#include <vector>

#include "softpbr/image/image.h"
#include "softpbr/image/load.h"

namespace softpbr::image::detail {

// stb_image's reading of the header: the size, or "<name>: not a readable image (why)".
struct StbSize {
  int width = 0;
  int height = 0;
};
StbSize stb_info(std::span<const std::uint8_t> bytes, std::string_view name);

// The whole image decoded to RGBA8 (grey replicated, alpha 255 when absent).
// The buffer is reserved to capacity(width, height) bytes when `capacity` is given.
Image8 stb_load_rgba8(std::span<const std::uint8_t> bytes, std::string_view name, Capacity capacity = nullptr);

// The pixels stb_image returns, freed with stbi_image_free.
struct StbFree {
  void operator()(void* p) const;
};

// A Radiance .hdr decoded to float RGB (width × height × 3 values), or "<name>: cannot
// decode (why)".
std::unique_ptr<float[], StbFree> stb_load_rgb_float(std::span<const std::uint8_t> bytes, std::string_view name,
                                                     int& width, int& height);

// `rgb` (width × height × 3 floats, each finite and ≥ 0) as a Radiance RGBE file.
std::vector<std::uint8_t> stb_encode_hdr(std::span<const float> rgb, int width, int height, std::string_view name);

}  // namespace softpbr::image::detail
