// Helpers for the texture-file suites (test_scene_textures.cpp, test_obj_textures.cpp):
// a scratch folder per test case, small PNGs written with image::write_png, and PNGs
// written byte by byte for what stb_image_write cannot make — 16-bit samples, a header
// declaring any size, a file cut short.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "softpbr/image/image.h"
#include "softpbr/image/write.h"

namespace texture_test {

namespace fs = std::filesystem;

// An empty folder of its own for one test case (ctest runs test cases in parallel).
inline fs::path scratch(const std::string& name) {
  const fs::path dir = fs::path(SOFTPBR_BINARY_DIR) / "texture-test" / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

inline void write_text(const fs::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary | std::ios::trunc) << text;
}

inline void write_bytes(const fs::path& path, const std::vector<std::uint8_t>& bytes) {
  std::ofstream(path, std::ios::binary | std::ios::trunc)
      .write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

// A w×h image whose texel (x, y) is f(x, y) → {r, g, b, a}.
template <class F>
softpbr::image::Image8 image_of(int w, int h, F&& f) {
  softpbr::image::Image8 im{w, h, std::vector<std::uint8_t>(static_cast<std::size_t>(w) * h * 4)};
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const std::array<std::uint8_t, 4> c = f(x, y);
      for (int k = 0; k < 4; ++k) im.rgba[(static_cast<std::size_t>(y) * w + x) * 4 + k] = c[k];
    }
  return im;
}

inline softpbr::image::Image8 solid(int w, int h, std::uint8_t r, std::uint8_t g, std::uint8_t b, std::uint8_t a = 255) {
  return image_of(w, h, [&](int, int) { return std::array<std::uint8_t, 4>{r, g, b, a}; });
}

// ---- PNG files byte by byte (ISO/IEC 15948): signature, chunks with CRC-32, zlib data in
// stored (uncompressed) deflate blocks, so no encoder is needed.

inline std::uint32_t crc32(const std::uint8_t* p, std::size_t n) {
  std::uint32_t c = 0xffffffffu;
  for (std::size_t i = 0; i < n; ++i) {
    c ^= p[i];
    for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xedb88320u & (0u - (c & 1u)));
  }
  return c ^ 0xffffffffu;
}

inline void put32(std::vector<std::uint8_t>& out, std::uint32_t v) {
  for (int s = 24; s >= 0; s -= 8) out.push_back(static_cast<std::uint8_t>(v >> s));
}

inline void chunk(std::vector<std::uint8_t>& out, const char* type, const std::vector<std::uint8_t>& data) {
  put32(out, static_cast<std::uint32_t>(data.size()));
  const std::size_t start = out.size();
  out.insert(out.end(), type, type + 4);
  out.insert(out.end(), data.begin(), data.end());
  put32(out, crc32(out.data() + start, out.size() - start));
}

// zlib (RFC 1950) of `raw` in stored deflate blocks (RFC 1951 §3.2.4).
inline std::vector<std::uint8_t> zlib_stored(const std::vector<std::uint8_t>& raw) {
  std::vector<std::uint8_t> z = {0x78, 0x01};
  std::size_t at = 0;
  do {
    const std::size_t n = std::min<std::size_t>(raw.size() - at, 65535);
    z.push_back(at + n == raw.size() ? 1 : 0);
    z.push_back(static_cast<std::uint8_t>(n));
    z.push_back(static_cast<std::uint8_t>(n >> 8));
    z.push_back(static_cast<std::uint8_t>(~n));
    z.push_back(static_cast<std::uint8_t>(~n >> 8));
    z.insert(z.end(), raw.begin() + static_cast<std::ptrdiff_t>(at), raw.begin() + static_cast<std::ptrdiff_t>(at + n));
    at += n;
  } while (at < raw.size());
  std::uint32_t a = 1, b = 0;
  for (const std::uint8_t byte : raw) a = (a + byte) % 65521, b = (b + a) % 65521;
  put32(z, b << 16 | a);
  return z;
}

// A PNG whose IHDR declares w × h at `bit_depth` and `color_type`, with `scanlines` (filter
// bytes included) as its image data — which need not match the declared size.
inline std::vector<std::uint8_t> png_bytes(std::uint32_t w, std::uint32_t h, int bit_depth, int color_type,
                                           const std::vector<std::uint8_t>& scanlines) {
  std::vector<std::uint8_t> out = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  std::vector<std::uint8_t> ihdr;
  put32(ihdr, w);
  put32(ihdr, h);
  ihdr.insert(ihdr.end(), {static_cast<std::uint8_t>(bit_depth), static_cast<std::uint8_t>(color_type), 0, 0, 0});
  chunk(out, "IHDR", ihdr);
  chunk(out, "IDAT", zlib_stored(scanlines));
  chunk(out, "IEND", {});
  return out;
}

// A 16-bit RGB PNG (colour type 2) of w × h with every sample `value`.
inline std::vector<std::uint8_t> png16(int w, int h, std::uint16_t value) {
  std::vector<std::uint8_t> lines;
  for (int y = 0; y < h; ++y) {
    lines.push_back(0);  // filter: none
    for (int i = 0; i < w * 3; ++i) {
      lines.push_back(static_cast<std::uint8_t>(value >> 8));
      lines.push_back(static_cast<std::uint8_t>(value));
    }
  }
  return png_bytes(static_cast<std::uint32_t>(w), static_cast<std::uint32_t>(h), 16, 2, lines);
}

// An 8-bit RGBA PNG header declaring w × h over one row of pixel data: a decoder that
// trusted the header would allocate w × h × 4 bytes.
inline std::vector<std::uint8_t> png_declaring(std::uint32_t w, std::uint32_t h) {
  return png_bytes(w, h, 8, 6, std::vector<std::uint8_t>(1 + 4 * 4, 0));
}

// A valid PNG of `image` cut to its first `keep` bytes.
inline std::vector<std::uint8_t> truncated_png(const softpbr::image::Image8& image, std::size_t keep) {
  std::vector<std::uint8_t> png = softpbr::image::encode_png(image, "truncated.png");
  png.resize(std::min(keep, png.size()));
  return png;
}

}  // namespace texture_test
