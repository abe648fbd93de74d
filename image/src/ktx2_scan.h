// Internal to softpbr_image: a KTX 2.0 file's structure checked before anything is
// allocated or decoded — the header, the level index, the data format descriptor (DFD),
// the key/value data and the supercompression global data, every offset and length
// against the file, the sizes against Limits (KTX File Format Specification 2.0, §3–§4).
#pragma once

#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

#include "softpbr/image/image.h"
#include "softpbr/image/ktx2.h"

namespace softpbr::image::detail {

enum class Ktx2Codec { Raw, Uastc, Etc1s };

struct Ktx2Level {
  std::uint64_t offset = 0, length = 0;  // inside the file
  std::uint64_t data_bytes = 0;          // after supercompression is undone
  int width = 0, height = 0;
};

struct Ktx2Scan {
  Ktx2Info info;
  Ktx2Codec codec = Ktx2Codec::Raw;
  int texel_bytes = 4;           // Raw: 1 to 4 (R, RG, RGB, RGBA)
  int supercompression = 0;      // 0 none, 1 BasisLZ, 2 Zstandard
  bool flip_y = false;           // KTXorientation "ru": rows stored bottom up
  bool etc1s_alpha = false;      // ETC1S: the DFD's second sample is alpha (alpha slices)
  std::uint64_t sgd_offset = 0, sgd_length = 0;  // the supercompression global data
  std::vector<Ktx2Level> levels; // level 0 first
};

// The 12-byte identifier «KTX 20»\r\n\x1A\n (§3.1).
bool is_ktx2(std::span<const std::uint8_t> bytes);

// last_level for ktx2_scan: every level.
inline constexpr int kAllKtx2Levels = 1 << 30;

// Throws "<name>: <what is wrong>" unless the file is a KTX2 file this reader decodes and
// every level's data lies inside it (BasisLZ slices are checked when decoded: etc1s.h). The decoded RGBA of levels [0, last_level] plus the
// largest Zstandard level's blocks (or ETC1S level's decoded blocks) must fit
// limits.max_decoded_bytes.
Ktx2Scan ktx2_scan(std::span<const std::uint8_t> file, std::string_view name, const Limits& limits, int last_level);

// The header's and the DFD's description, nothing checked (read_ktx2_info).
Ktx2Info ktx2_describe(std::span<const std::uint8_t> file);

}  // namespace softpbr::image::detail
