// Helpers shared by the softpbr::golden test suites: scratch folders, small images.
#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "softpbr/golden/image.h"

namespace golden_test {

namespace fs = std::filesystem;

// An empty folder of its own for one test case (ctest runs test cases in parallel).
inline fs::path scratch(const std::string& name) {
  const fs::path dir = fs::path(SOFTPBR_BINARY_DIR) / "golden-test" / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

// A w×h 8-bit image whose samples are a pattern of x, y and the channel, so that every
// pixel differs from its neighbours.
inline softpbr::raster::Image8 pattern8(int w, int h, int seed = 0) {
  softpbr::raster::Image8 im{w, h, std::vector<std::uint8_t>(static_cast<std::size_t>(w) * h * 4)};
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 4; ++c)
        im.rgba[(static_cast<std::size_t>(y) * w + x) * 4 + c] =
            static_cast<std::uint8_t>(c == 3 ? 255 : (x * 37 + y * 11 + c * 85 + seed) & 0xff);
  return im;
}

// A w×h float image with linear values spread over [0, 4) (HDR), alpha 1.
inline softpbr::golden::ImageF patternF(int w, int h) {
  softpbr::golden::ImageF im{w, h, std::vector<float>(static_cast<std::size_t>(w) * h * 4)};
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 4; ++c)
        im.rgba[(static_cast<std::size_t>(y) * w + x) * 4 + c] =
            c == 3 ? 1.0f : static_cast<float>((x * 7 + y * 3 + c * 5) % 64) / 16.0f + 0.01f * static_cast<float>(c);
  return im;
}

inline std::vector<char> file_bytes(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

inline void write_bytes(const fs::path& p, const std::string& bytes) {
  std::ofstream(p, std::ios::binary) << bytes;
}

}  // namespace golden_test
