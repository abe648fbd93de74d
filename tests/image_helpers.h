// Helpers shared by the softpbr::image test suites, beside golden_helpers.h's: files as
// bytes, smooth images and JPEGs written by stb_image_write.
#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <stb_image_write.h>

#include "golden_helpers.h"
#include "softpbr/image/image.h"

namespace image_test {

namespace fs = std::filesystem;

using golden_test::patternF;  // a float pattern over [0, 4)
using golden_test::scratch;   // an empty folder per test case

inline std::vector<std::uint8_t> read_bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

inline void write_bytes(const fs::path& path, const std::vector<std::uint8_t>& bytes) {
  std::ofstream(path, std::ios::binary | std::ios::trunc)
      .write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

inline std::size_t files_in(const fs::path& dir) {
  return static_cast<std::size_t>(std::distance(fs::directory_iterator(dir), fs::directory_iterator()));
}

// A smooth w×h RGBA pattern (JPEG keeps smooth images close to their values).
inline softpbr::image::Image8 smooth8(int w, int h) {
  softpbr::image::Image8 im{w, h, std::vector<std::uint8_t>(static_cast<std::size_t>(w) * h * 4)};
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      std::uint8_t* p = &im.rgba[(static_cast<std::size_t>(y) * w + x) * 4];
      p[0] = static_cast<std::uint8_t>(60 + 2 * x);
      p[1] = static_cast<std::uint8_t>(90 + 3 * y);
      p[2] = 128;
      p[3] = 255;
    }
  return im;
}

// The first `components` channels of `image` as a baseline JPEG from stbi_write_jpg (1:
// the red channel as grey; 4: stb ignores alpha). stb always writes three components
// (YCbCr; grey has flat chroma) and subsamples chroma 4:2:0 at quality <= 90.
inline std::vector<std::uint8_t> jpeg_of(const softpbr::image::Image8& image, int components, int quality) {
  std::vector<std::uint8_t> samples;
  for (std::size_t i = 0; i < image.rgba.size(); i += 4)
    for (int c = 0; c < components; ++c) samples.push_back(image.rgba[i + static_cast<std::size_t>(c)]);
  std::vector<std::uint8_t> out;
  stbi_write_jpg_to_func(
      [](void* context, void* data, int size) {
        auto* o = static_cast<std::vector<std::uint8_t>*>(context);
        o->insert(o->end(), static_cast<std::uint8_t*>(data), static_cast<std::uint8_t*>(data) + size);
      },
      &out, image.width, image.height, components, samples.data(), quality);
  return out;
}

// The offset of the first marker FF `code` in a JPEG, or 0.
inline std::size_t find_marker(const std::vector<std::uint8_t>& jpeg, std::uint8_t code) {
  for (std::size_t i = 2; i + 1 < jpeg.size(); ++i)
    if (jpeg[i] == 0xff && jpeg[i + 1] == code) return i;
  return 0;
}

}  // namespace image_test
