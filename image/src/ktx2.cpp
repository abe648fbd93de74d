// KTX2 levels decoded to RGBA8 (see softpbr/image/ktx2.h): the structure checked by
// ktx2_scan, a Zstandard level inflated into a buffer of exactly the size the level index
// gives, then its blocks (uastc.h) or texels expanded.
#include <zstd.h>

#include <algorithm>
#include <cstring>
#include <new>

#include "etc1s.h"
#include "formats.h"
#include "ktx2_scan.h"
#include "softpbr/image/ktx2.h"
#include "uastc.h"

namespace softpbr::image {

namespace {

// The level's stored bytes after supercompression is undone: the file's own bytes, or
// `inflated` filled from Zstandard.
std::span<const std::uint8_t> level_data(std::span<const std::uint8_t> file, const detail::Ktx2Scan& s, int l,
                                         std::string_view name, std::vector<std::uint8_t>& inflated) {
  const detail::Ktx2Level& lv = s.levels[static_cast<std::size_t>(l)];
  const std::span<const std::uint8_t> stored = file.subspan(lv.offset, lv.length);
  if (s.supercompression != 2) return stored;  // none, or BasisLZ's slices
  inflated.resize(lv.data_bytes);
  // A frame may decompress to at most the buffer's size: ZSTD_decompress stops with an
  // error there, so a bomb costs nothing beyond the bound already checked.
  const std::size_t got = ZSTD_decompress(inflated.data(), inflated.size(), stored.data(), stored.size());
  if (ZSTD_isError(got))
    detail::fail(name, "level " + std::to_string(l) + ": cannot decode its Zstandard data (" + ZSTD_getErrorName(got) + ")");
  if (got != inflated.size())
    detail::fail(name, "level " + std::to_string(l) + ": its Zstandard data inflates to " + std::to_string(got) +
                           " bytes, not the level's " + std::to_string(inflated.size()));
  return inflated;
}

// A level's ETC1S slices (etc1s.h): colour, then alpha from the alpha slice when the
// DFD has one (else alpha 255).
void decode_etc1s(std::span<const std::uint8_t> level, const detail::Ktx2Scan& s, const detail::Etc1sGlobal& g,
                  Image8& out, int l, std::string_view name) {
  const std::string where = "level " + std::to_string(l) + ": ";
  const detail::Etc1sImageDesc& d = g.images[static_cast<std::size_t>(l)];
  if (d.flags & 2) detail::fail(name, where + "is a video P-frame (not a texture)");
  auto slice = [&](std::uint64_t offset, std::uint64_t length, const char* what) {
    if (length == 0 || offset > level.size() || length > level.size() - offset)
      detail::fail(name, where + "its " + what + " slice (bytes " + std::to_string(offset) + " + " + std::to_string(length) +
                             ") does not lie inside the level's " + std::to_string(level.size()) + " bytes");
    return level.subspan(offset, length);
  };
  std::fill(out.rgba.begin(), out.rgba.end(), std::uint8_t{255});
  std::string problem = detail::etc1s_decode_slice(g, slice(d.rgb_offset, d.rgb_length, "colour"), out.width, out.height,
                                                   out.rgba.data(), false);
  if (problem.empty() && s.etc1s_alpha)
    problem = detail::etc1s_decode_slice(g, slice(d.alpha_offset, d.alpha_length, "alpha"), out.width, out.height,
                                         out.rgba.data(), true);
  if (!problem.empty()) detail::fail(name, where + problem);
}

void decode_uastc(std::span<const std::uint8_t> data, Image8& out, int l, std::string_view name) {
  const int bw = (out.width + 3) / 4, bh = (out.height + 3) / 4;
  // ktx2_scan made the level exactly this long; checked again where the blocks are read.
  if (data.size() < static_cast<std::size_t>(bw) * static_cast<std::size_t>(bh) * 16)
    detail::fail(name, "level " + std::to_string(l) + ": its UASTC data is shorter than its blocks");
  std::uint8_t texels[64];
  for (int by = 0; by < bh; ++by)
    for (int bx = 0; bx < bw; ++bx) {
      const std::uint8_t* block = data.data() + (static_cast<std::size_t>(by) * bw + bx) * 16;
      if (!detail::decode_uastc_block(block, texels))
        detail::fail(name, "level " + std::to_string(l) + ": block (" + std::to_string(bx) + ", " + std::to_string(by) +
                               ") is not a valid UASTC block");
      // The block's texels inside the level (a level's last blocks may overhang it).
      const int rows = std::min(4, out.height - by * 4), cols = std::min(4, out.width - bx * 4);
      for (int y = 0; y < rows; ++y)
        std::memcpy(&out.rgba[((static_cast<std::size_t>(by) * 4 + y) * out.width + bx * 4) * 4], texels + y * 16,
                    static_cast<std::size_t>(cols) * 4);
    }
}

// R, RG, RGB or RGBA bytes to RGBA as Vulkan samples them: absent G and B are 0, absent A 255.
void expand_raw(std::span<const std::uint8_t> data, Image8& out, int texel_bytes) {
  const std::size_t texels = static_cast<std::size_t>(out.width) * out.height;
  for (std::size_t i = 0; i < texels; ++i) {
    std::uint8_t* d = &out.rgba[i * 4];
    const std::uint8_t* s = &data[i * static_cast<std::size_t>(texel_bytes)];
    d[0] = s[0];
    d[1] = texel_bytes > 1 ? s[1] : 0;
    d[2] = texel_bytes > 2 ? s[2] : 0;
    d[3] = texel_bytes > 3 ? s[3] : 255;
  }
}

void flip_rows(Image8& im) {
  const std::size_t row = static_cast<std::size_t>(im.width) * 4;
  for (int y = 0; y < im.height / 2; ++y)
    std::swap_ranges(im.rgba.begin() + static_cast<std::ptrdiff_t>(y * row),
                     im.rgba.begin() + static_cast<std::ptrdiff_t>((y + 1) * row),
                     im.rgba.begin() + static_cast<std::ptrdiff_t>((im.height - 1 - y) * row));
}

Image8 decode_level(std::span<const std::uint8_t> file, const detail::Ktx2Scan& s, const detail::Etc1sGlobal& g, int l,
                    std::string_view name, Capacity capacity, std::vector<std::uint8_t>& scratch) {
  const detail::Ktx2Level& lv = s.levels[static_cast<std::size_t>(l)];
  const std::span<const std::uint8_t> data = level_data(file, s, l, name, scratch);
  Image8 out;
  out.width = lv.width;
  out.height = lv.height;
  const std::size_t size = static_cast<std::size_t>(lv.width) * lv.height * 4;
  try {
    if (capacity != nullptr) out.rgba.reserve(std::max(size, capacity(lv.width, lv.height)));
    out.rgba.resize(size);
  } catch (const std::bad_alloc&) {
    detail::fail(name, "cannot decode (out of memory for " + std::to_string(size) + " bytes of pixels)");
  }
  if (s.codec == detail::Ktx2Codec::Uastc) decode_uastc(data, out, l, name);
  else if (s.codec == detail::Ktx2Codec::Etc1s) decode_etc1s(data, s, g, out, l, name);
  else expand_raw(data, out, s.texel_bytes);
  if (s.flip_y) flip_rows(out);
  return out;
}

// BasisLZ's codebooks and tables (nothing for other schemes).
detail::Etc1sGlobal read_global(std::span<const std::uint8_t> file, const detail::Ktx2Scan& s, std::string_view name) {
  detail::Etc1sGlobal g;
  if (s.codec != detail::Ktx2Codec::Etc1s) return g;
  const std::string problem =
      detail::etc1s_read_global(file.subspan(s.sgd_offset, s.sgd_length), static_cast<int>(s.levels.size()), g);
  if (!problem.empty()) detail::fail(name, problem);
  return g;
}

}  // namespace

Ktx2Image load_ktx2(std::span<const std::uint8_t> bytes, std::string_view name, const Limits& limits) {
  return load_ktx2(bytes, name, limits, nullptr);
}

Ktx2Image load_ktx2(std::span<const std::uint8_t> bytes, std::string_view name, const Limits& limits, Capacity capacity) {
  const detail::Ktx2Scan s = detail::ktx2_scan(bytes, name, limits, detail::kAllKtx2Levels);
  Ktx2Image out;
  out.info = s.info;
  const detail::Etc1sGlobal g = read_global(bytes, s, name);
  std::vector<std::uint8_t> scratch;
  for (int l = 0; l < static_cast<int>(s.levels.size()); ++l)
    out.levels.push_back(decode_level(bytes, s, g, l, name, l == 0 ? capacity : nullptr, scratch));
  return out;
}

bool is_ktx2(std::span<const std::uint8_t> bytes) { return detail::is_ktx2(bytes); }

Ktx2Image load_ktx2(const std::filesystem::path& path, const Limits& limits) {
  return load_ktx2(detail::read_file(path, limits), path.string(), limits);
}

Ktx2Info read_ktx2_info(std::span<const std::uint8_t> bytes) { return detail::ktx2_describe(bytes); }

Image8 detail::ktx2_rgba8(std::span<const std::uint8_t> bytes, std::string_view name, const Limits& limits,
                          Capacity capacity) {
  const Ktx2Scan s = ktx2_scan(bytes, name, limits, 0);
  const Etc1sGlobal g = read_global(bytes, s, name);
  std::vector<std::uint8_t> scratch;
  return decode_level(bytes, s, g, 0, name, capacity, scratch);
}

}  // namespace softpbr::image
