// A minimal KTX 2.0 writer for the KTX2 test suites: a 2D texture's levels as given
// (uncompressed texels, UASTC blocks or BasisLZ slices with their global data), optionally
// Zstandard-compressed, with a basic data format descriptor of one or two samples. Not a
// general writer: it writes what the tests need and the fields the reader checks (KTX File
// Format Specification 2.0, §3). etc1s_writer.h makes BasisLZ data.
#pragma once

#include <zstd.h>

#include <cstdint>
#include <string>
#include <vector>

namespace ktx2_test {

struct Ktx2Spec {
  std::uint32_t vk_format = 37;  // VK_FORMAT_R8G8B8A8_UNORM; 0 with color_model 166 for UASTC
  int width = 0, height = 0;
  std::uint32_t depth = 0, layers = 0, faces = 1;
  std::uint32_t level_count = 0;  // 0: levels.size()
  std::uint32_t scheme = 0;       // 0 none, 2 Zstandard
  int color_model = 1;            // KHR_DF_MODEL_RGBSDA; 166 UASTC, 163 ETC1S
  int samples = 1;                // DFD samples: ETC1S with alpha slices has 2 (RGB, AAA)
  std::vector<std::uint8_t> sgd;  // supercompression global data (BasisLZ)
  int transfer = 1;               // 1 linear, 2 sRGB
  std::string orientation;        // a KTXorientation value ("rd", "ru"), or none
  std::vector<std::vector<std::uint8_t>> levels;  // level 0 first
};

inline void put32(std::vector<std::uint8_t>& b, std::size_t at, std::uint64_t v) {
  for (int i = 0; i < 4; ++i) b[at + static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(v >> (8 * i));
}
inline void put64(std::vector<std::uint8_t>& b, std::size_t at, std::uint64_t v) {
  put32(b, at, v & 0xFFFFFFFFu);
  put32(b, at + 4, v >> 32);
}

inline std::vector<std::uint8_t> write_ktx2(const Ktx2Spec& s) {
  const std::size_t levels = s.levels.size();
  std::vector<std::uint8_t> b(80 + 24 * levels, 0);
  const std::uint8_t id[12] = {0xAB, 'K', 'T', 'X', ' ', '2', '0', 0xBB, '\r', '\n', 0x1A, '\n'};
  for (int i = 0; i < 12; ++i) b[static_cast<std::size_t>(i)] = id[i];
  put32(b, 12, s.vk_format);
  put32(b, 16, s.vk_format == 0 ? 1 : 1);  // typeSize: 1 for 8-bit formats and block formats
  put32(b, 20, static_cast<std::uint32_t>(s.width));
  put32(b, 24, static_cast<std::uint32_t>(s.height));
  put32(b, 28, s.depth);
  put32(b, 32, s.layers);
  put32(b, 36, s.faces);
  put32(b, 40, s.level_count ? s.level_count : static_cast<std::uint32_t>(levels));
  put32(b, 44, s.scheme);
  // DFD: dfdTotalSize, then a basic block of 24 bytes plus 16 bytes a sample.
  const std::size_t dfd = b.size(), dfd_bytes = 28 + 16 * static_cast<std::size_t>(s.samples);
  b.resize(dfd + dfd_bytes, 0);
  put32(b, dfd, dfd_bytes);
  put32(b, dfd + 4, 0);                                   // vendor Khronos, descriptor type basic
  put32(b, dfd + 8, 2 | ((dfd_bytes - 4) << 16));         // version 2, block size
  b[dfd + 12] = static_cast<std::uint8_t>(s.color_model);
  b[dfd + 13] = 1;                        // BT.709 primaries
  b[dfd + 14] = static_cast<std::uint8_t>(s.transfer);
  const bool blocks = s.color_model == 166 || s.color_model == 163;
  b[dfd + 16] = blocks ? 3 : 0;  // texel block 4×4 (dimension − 1) for UASTC and ETC1S
  b[dfd + 17] = blocks ? 3 : 0;
  for (int k = 0; k < s.samples; ++k) {
    b[dfd + 28 + 16 * static_cast<std::size_t>(k) + 2] = s.color_model == 166 ? 127 : s.color_model == 163 ? 63 : 7;  // bitLength − 1
    b[dfd + 28 + 16 * static_cast<std::size_t>(k) + 3] = k == 1 ? 15 : 0;  // channel: colour, then alpha (AAA)
  }
  put32(b, 48, dfd);
  put32(b, 52, dfd_bytes);
  // Key/value data: KTXorientation.
  if (!s.orientation.empty()) {
    const std::string kv = std::string("KTXorientation") + '\0' + s.orientation + '\0';
    const std::size_t at = b.size();
    b.resize(at + 4 + ((kv.size() + 3) & ~std::size_t{3}), 0);
    put32(b, at, kv.size());
    for (std::size_t i = 0; i < kv.size(); ++i) b[at + 4 + i] = static_cast<std::uint8_t>(kv[i]);
    put32(b, 56, at);
    put32(b, 60, b.size() - at);
  }
  if (!s.sgd.empty()) {
    while (b.size() % 8) b.push_back(0);
    put64(b, 64, b.size());
    put64(b, 72, s.sgd.size());
    b.insert(b.end(), s.sgd.begin(), s.sgd.end());
  }
  // The levels' data, smallest level first as the specification recommends.
  for (std::size_t l = levels; l-- > 0;) {
    std::vector<std::uint8_t> data = s.levels[l];
    if (s.scheme == 2) {
      std::vector<std::uint8_t> z(ZSTD_compressBound(data.size()));
      z.resize(ZSTD_compress(z.data(), z.size(), data.data(), data.size(), 3));
      data = z;
    }
    while (b.size() % 16) b.push_back(0);
    put64(b, 80 + 24 * l, b.size());
    put64(b, 80 + 24 * l + 8, data.size());
    put64(b, 80 + 24 * l + 16, s.scheme == 1 ? 0 : s.levels[l].size());  // BasisLZ: 0 (§3.9.7)
    b.insert(b.end(), data.begin(), data.end());
  }
  return b;
}

}  // namespace ktx2_test
