// The KTX2 structure walk (see ktx2_scan.h). Sections are the KTX File Format
// Specification 2.0's; DFD fields are the Khronos Data Format Specification 1.3's (§5.5,
// the basic descriptor block).
#include "ktx2_scan.h"

#include <algorithm>
#include <array>
#include <bit>
#include <string>

#include "formats.h"

namespace softpbr::image::detail {

namespace {

constexpr std::array<std::uint8_t, 12> kIdentifier = {0xAB, 'K', 'T', 'X', ' ', '2', '0', 0xBB, '\r', '\n', 0x1A, '\n'};
constexpr std::size_t kHeaderBytes = 80;     // identifier, 9 header fields, the index (§3.1–§3.5)
constexpr std::size_t kLevelEntryBytes = 24;  // byteOffset, byteLength, uncompressedByteLength
constexpr int kMaxLevels = 15;                // ⌊log₂ 16384⌋ + 1

constexpr int kColorModelEtc1s = 163;  // KHR_DF_MODEL_ETC1S
constexpr int kColorModelUastc = 166;  // KHR_DF_MODEL_UASTC
constexpr int kTransferSrgb = 2;       // KHR_DF_TRANSFER_SRGB

struct RawFormat {
  std::uint32_t vk_format;
  int texel_bytes;
  const char* name;
};
// The uncompressed vkFormats read (Vulkan's VkFormat values).
constexpr std::array<RawFormat, 8> kRawFormats = {{
    {9, 1, "R8_UNORM"},
    {15, 1, "R8_SRGB"},
    {16, 2, "R8G8_UNORM"},
    {22, 2, "R8G8_SRGB"},
    {23, 3, "R8G8B8_UNORM"},
    {29, 3, "R8G8B8_SRGB"},
    {37, 4, "R8G8B8A8_UNORM"},
    {43, 4, "R8G8B8A8_SRGB"},
}};

std::uint32_t u32(std::span<const std::uint8_t> b, std::size_t at) {
  return std::uint32_t{b[at]} | (std::uint32_t{b[at + 1]} << 8) | (std::uint32_t{b[at + 2]} << 16) |
         (std::uint32_t{b[at + 3]} << 24);
}
std::uint64_t u64(std::span<const std::uint8_t> b, std::size_t at) {
  return std::uint64_t{u32(b, at)} | (std::uint64_t{u32(b, at + 4)} << 32);
}

const char* supercompression_name(std::uint32_t scheme) {
  switch (scheme) {
    case 0: return "none";
    case 1: return "BasisLZ";
    case 2: return "Zstandard";
    case 3: return "ZLIB";
    default: return "";
  }
}

// Whether [offset, offset + length) lies inside a file of `size` bytes, without overflow.
bool inside(std::uint64_t offset, std::uint64_t length, std::uint64_t size) {
  return offset <= size && length <= size - offset;
}

std::string range_text(std::uint64_t offset, std::uint64_t length) {
  return "bytes " + std::to_string(offset) + " to " + std::to_string(offset) + " + " + std::to_string(length);
}

// The basic DFD block's colour model, transfer function and first sample's channel id, or
// -1 where the descriptor is too short to hold them.
struct Dfd {
  int color_model = -1, transfer = -1, channel0 = -1, samples = 0;
};
Dfd read_dfd(std::span<const std::uint8_t> file, std::uint32_t offset, std::uint32_t length) {
  Dfd d;
  if (!inside(offset, length, file.size()) || length < 4 + 24) return d;
  const std::size_t block = std::size_t{offset} + 4;  // after dfdTotalSize
  d.color_model = file[block + 8];
  d.transfer = file[block + 10];
  const std::uint32_t block_size = u32(file, block + 4) >> 16;
  if (block_size >= 24 && block_size <= length - 4) {
    d.samples = static_cast<int>((block_size - 24) / 16);
    if (d.samples > 0) d.channel0 = file[block + 24 + 3] & 0xF;
  }
  return d;
}

}  // namespace

bool is_ktx2(std::span<const std::uint8_t> bytes) {
  return bytes.size() >= kIdentifier.size() && std::equal(kIdentifier.begin(), kIdentifier.end(), bytes.begin());
}

Ktx2Info ktx2_describe(std::span<const std::uint8_t> file) {
  Ktx2Info info;
  if (!is_ktx2(file) || file.size() < kHeaderBytes) return info;
  const std::uint32_t vk_format = u32(file, 12);
  info.width = static_cast<int>(std::min<std::uint32_t>(u32(file, 20), 1u << 30));
  info.height = static_cast<int>(std::min<std::uint32_t>(u32(file, 24), 1u << 30));
  info.levels = static_cast<int>(std::clamp<std::uint32_t>(u32(file, 40), 1, 1u << 30));
  info.supercompression = supercompression_name(u32(file, 44));
  const Dfd dfd = read_dfd(file, u32(file, 48), u32(file, 52));
  info.srgb = dfd.transfer == kTransferSrgb;
  if (vk_format == 0) {
    info.format = dfd.color_model == kColorModelUastc ? "UASTC"
                  : dfd.color_model == kColorModelEtc1s ? "ETC1S"
                                                        : "vkFormat 0, colour model " + std::to_string(dfd.color_model);
  } else {
    info.format = "vkFormat " + std::to_string(vk_format);
    for (const RawFormat& f : kRawFormats)
      if (f.vk_format == vk_format) info.format = f.name;
  }
  return info;
}

Ktx2Scan ktx2_scan(std::span<const std::uint8_t> file, std::string_view name, const Limits& limits, int last_level) {
  if (!is_ktx2(file)) fail(name, "not a KTX2 file (no KTX 2.0 identifier)");
  if (file.size() < kHeaderBytes)
    fail(name, "truncated: " + std::to_string(file.size()) + " bytes, less than a KTX2 header (80 bytes)");
  Ktx2Scan s;
  s.info = ktx2_describe(file);
  const std::uint32_t vk_format = u32(file, 12);
  const std::uint32_t width = u32(file, 20), height = u32(file, 24), depth = u32(file, 28);
  const std::uint32_t layers = u32(file, 32), faces = u32(file, 36), level_count = u32(file, 40);
  const std::uint32_t scheme = u32(file, 44);

  // §3.4: what kind of texture.
  if (depth != 0) fail(name, "is a 3D texture (depth " + std::to_string(depth) + "); only 2D KTX2 textures are read");
  if (layers > 1) fail(name, "is a texture array (" + std::to_string(layers) + " layers); only 2D KTX2 textures are read");
  if (faces == 6) fail(name, "is a cube map; only 2D KTX2 textures are read");
  if (faces != 1) fail(name, "faceCount is " + std::to_string(faces) + " (1 for a 2D texture, 6 for a cube map)");
  if (height == 0) fail(name, "is a 1D texture (pixelHeight 0); only 2D KTX2 textures are read");
  check_size(name, width, height, 4, limits);  // sides first: a 65536² header stops here
  const int w = static_cast<int>(width), h = static_cast<int>(height);
  const int max_levels = std::bit_width(static_cast<unsigned>(std::max(w, h)));
  const int levels = level_count == 0 ? 1 : static_cast<int>(std::min<std::uint32_t>(level_count, kMaxLevels + 1));
  if (levels > max_levels)
    fail(name, "levelCount " + std::to_string(level_count) + " is more than a " + std::to_string(w) + "x" +
                   std::to_string(h) + " texture has (" + std::to_string(max_levels) + ")");

  // §3.7 supercompression; §3.1 vkFormat with the DFD's colour model.
  s.supercompression = static_cast<int>(scheme);
  if (scheme == 3) fail(name, "ZLIB supercompression is not supported (none and Zstandard are)");
  if (scheme > 3) fail(name, "unknown supercompression scheme " + std::to_string(scheme));
  const std::uint32_t dfd_offset = u32(file, 48), dfd_length = u32(file, 52);
  if (!inside(dfd_offset, dfd_length, file.size()))
    fail(name, "its data format descriptor (" + range_text(dfd_offset, dfd_length) + ") lies past the end of the file (" +
                   std::to_string(file.size()) + " bytes)");
  if (dfd_length < 4 + 24 || u32(file, dfd_offset) != dfd_length)
    fail(name, "its data format descriptor is malformed (dfdTotalSize does not match dfdByteLength, or too short)");
  const Dfd dfd = read_dfd(file, dfd_offset, dfd_length);
  if (u32(file, dfd_offset + 4) != 0)
    fail(name, "its data format descriptor does not begin with a Khronos basic descriptor block");
  std::uint64_t block_bytes = 0;  // 0: uncompressed
  if (vk_format == 0) {
    if (dfd.color_model == kColorModelUastc) {
      // (fuzz_ktx2: UASTC under BasisLZ had its blocks read past the level's end.)
      if (scheme == 1) fail(name, "BasisLZ supercompression of UASTC data is invalid (it holds ETC1S only)");
      s.codec = Ktx2Codec::Uastc;
      block_bytes = 16;
    } else if (dfd.color_model == kColorModelEtc1s) {
      if (scheme != 1) fail(name, "ETC1S data without BasisLZ supercompression is invalid");
      s.codec = Ktx2Codec::Etc1s;
      // The samples: colour (RGB, RRR or GGG), then alpha (AAA, channel 15) when present.
      s.etc1s_alpha = dfd.samples >= 2;
    } else {
      fail(name, "vkFormat 0 with colour model " + std::to_string(dfd.color_model) +
                     " is not a format this reader decodes (UASTC, or the 8-bit R/RG/RGB/RGBA formats)");
    }
  } else {
    const auto f = std::find_if(kRawFormats.begin(), kRawFormats.end(),
                                [&](const RawFormat& r) { return r.vk_format == vk_format; });
    if (f == kRawFormats.end())
      fail(name, "vkFormat " + std::to_string(vk_format) +
                     " is not a format this reader decodes (UASTC, or the 8-bit R/RG/RGB/RGBA formats)");
    s.texel_bytes = f->texel_bytes;
    if (scheme == 1) fail(name, "BasisLZ supercompression of vkFormat " + std::to_string(vk_format) + " is invalid (it holds ETC1S only)");
    if (u32(file, 16) != 1) fail(name, "typeSize is " + std::to_string(u32(file, 16)) + " for an 8-bit format (1)");
  }

  // §3.10 key/value data: entries inside it; KTXorientation read.
  const std::uint32_t kvd_offset = u32(file, 56), kvd_length = u32(file, 60);
  if (!inside(kvd_offset, kvd_length, file.size()))
    fail(name, "its key/value data (" + range_text(kvd_offset, kvd_length) + ") lies past the end of the file");
  for (std::uint64_t at = kvd_offset, end = std::uint64_t{kvd_offset} + kvd_length; at + 4 <= end;) {
    const std::uint32_t entry = u32(file, at);
    if (entry > end - at - 4) fail(name, "a key/value entry at byte " + std::to_string(at) + " runs past the key/value data");
    const std::string_view kv(reinterpret_cast<const char*>(file.data() + at + 4), entry);
    constexpr std::string_view kOrientation("KTXorientation\0", 15);
    if (kv.starts_with(kOrientation) && kv.size() >= kOrientation.size() + 2) {
      const std::string_view value = kv.substr(kOrientation.size());
      if (value[0] != 'r') fail(name, "KTXorientation \"" + std::string(value.substr(0, 2)) + "\" (columns right to left) is not supported");
      s.flip_y = value[1] == 'u';
    }
    at += 4 + ((std::uint64_t{entry} + 3) & ~std::uint64_t{3});
  }
  // §3.11 supercompression global data: BasisLZ only.
  const std::uint64_t sgd_offset = u64(file, 64), sgd_length = u64(file, 72);
  if (!inside(sgd_offset, sgd_length, file.size()))
    fail(name, "its supercompression global data (" + range_text(sgd_offset, sgd_length) + ") lies past the end of the file");
  if (scheme == 1 && sgd_length == 0) fail(name, "BasisLZ supercompression without its global data");
  s.sgd_offset = sgd_offset;
  s.sgd_length = sgd_length;

  // §3.9 the level index.
  const std::uint64_t index_end = kHeaderBytes + kLevelEntryBytes * static_cast<std::uint64_t>(levels);
  if (index_end > file.size())
    fail(name, "truncated: its level index needs " + std::to_string(index_end) + " bytes, the file has " +
                   std::to_string(file.size()));
  std::uint64_t decoded = 0, scratch = 0;
  for (int l = 0; l < levels; ++l) {
    Ktx2Level lv;
    const std::size_t e = kHeaderBytes + kLevelEntryBytes * static_cast<std::size_t>(l);
    lv.offset = u64(file, e);
    lv.length = u64(file, e + 8);
    const std::uint64_t uncompressed = u64(file, e + 16);
    lv.width = std::max(1, w >> l);
    lv.height = std::max(1, h >> l);
    const std::uint64_t texels = std::uint64_t(lv.width) * std::uint64_t(lv.height);
    lv.data_bytes = block_bytes ? std::uint64_t((lv.width + 3) / 4) * std::uint64_t((lv.height + 3) / 4) * block_bytes
                                : texels * static_cast<std::uint64_t>(s.texel_bytes);
    const std::string where = "level " + std::to_string(l) + ": ";
    if (!inside(lv.offset, lv.length, file.size()))
      fail(name, where + "its data (" + range_text(lv.offset, lv.length) + ") lies past the end of the file (" +
                     std::to_string(file.size()) + " bytes)");
    if (scheme == 0 && (lv.length != lv.data_bytes || uncompressed != lv.data_bytes))
      fail(name, where + "its data is " + std::to_string(lv.length) + " bytes; a " + std::to_string(lv.width) + "x" +
                     std::to_string(lv.height) + " level of this format is " + std::to_string(lv.data_bytes));
    if (scheme == 2 && uncompressed != lv.data_bytes)
      fail(name, where + "uncompressedByteLength is " + std::to_string(uncompressed) + "; a " + std::to_string(lv.width) +
                     "x" + std::to_string(lv.height) + " level of this format is " + std::to_string(lv.data_bytes));
    if (scheme == 2 && lv.length == 0) fail(name, where + "its Zstandard data is empty");
    if (scheme == 1) lv.data_bytes = lv.length;  // slices of variable length (etc1s.h)
    if (l <= last_level) {
      decoded += texels * 4;
      if (scheme == 2) scratch = std::max(scratch, lv.data_bytes);
      if (scheme == 1)  // a level's ETC1S blocks, decoded before they are expanded (etc1s.h): 4 bytes a slice
        scratch = std::max(scratch, std::uint64_t((lv.width + 3) / 4) * std::uint64_t((lv.height + 3) / 4) *
                                        (s.etc1s_alpha ? 8u : 4u));
    }
    s.levels.push_back(lv);
  }
  // Everything decoded counts against the limit: the levels' RGBA after the first's and
  // one Zstandard level's blocks (or one ETC1S level's decoded blocks) at a time.
  check_size(name, w, h, 4, limits, decoded - std::uint64_t(w) * std::uint64_t(h) * 4 + scratch);
  return s;
}

}  // namespace softpbr::image::detail
