// KTX2 levels decoded to RGBA8 (see softpbr/image/ktx2.h): the structure checked by
// ktx2_scan, a Zstandard level inflated into a buffer of exactly the size the level index
// gives, then its blocks (uastc.h, etc1s.h) or texels expanded, in ranges of block rows that
// may run on the caller's threads.
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

// Block rows a task decodes: fixed, so that the ranges, and so the bytes and the first bad
// block reported, do not depend on the threads (ktx2.h's ParallelFor).
constexpr int kBlockRowsPerTask = 8;

// fn(task, by_begin, by_end) for the ranges of kBlockRowsPerTask of bh block rows, on
// `parallel` when it is given and there is more than one range.
template <class Fn>
void for_block_rows(int bh, const ParallelFor& parallel, Fn&& fn) {
  const std::size_t tasks = static_cast<std::size_t>((bh + kBlockRowsPerTask - 1) / kBlockRowsPerTask);
  auto task = [&](std::size_t t) {
    const int begin = static_cast<int>(t) * kBlockRowsPerTask;
    fn(t, begin, std::min(bh, begin + kBlockRowsPerTask));
  };
  if (parallel && tasks > 1) parallel(tasks, task);
  else for (std::size_t t = 0; t < tasks; ++t) task(t);
}

// A level's ETC1S slices (etc1s.h): colour, and alpha from the alpha slice when the DFD has
// one (else alpha 255). The slices' codes are read side by side on `parallel`, then the
// blocks expanded in ranges of block rows.
void decode_etc1s(std::span<const std::uint8_t> level, const detail::Ktx2Scan& s, const detail::Etc1sGlobal& g,
                  Image8& out, int l, std::string_view name, const ParallelFor& parallel) {
  const std::string where = "level " + std::to_string(l) + ": ";
  const detail::Etc1sImageDesc& d = g.images[static_cast<std::size_t>(l)];
  if (d.flags & 2) detail::fail(name, where + "is a video P-frame (not a texture)");
  auto slice = [&](std::uint64_t offset, std::uint64_t length, const char* what) {
    if (length == 0 || offset > level.size() || length > level.size() - offset)
      detail::fail(name, where + "its " + what + " slice (bytes " + std::to_string(offset) + " + " + std::to_string(length) +
                             ") does not lie inside the level's " + std::to_string(level.size()) + " bytes");
    return level.subspan(offset, length);
  };
  const std::span<const std::uint8_t> slices[2] = {slice(d.rgb_offset, d.rgb_length, "colour"),
                                                  s.etc1s_alpha ? slice(d.alpha_offset, d.alpha_length, "alpha")
                                                                : std::span<const std::uint8_t>()};
  const int bw = (out.width + 3) / 4, bh = (out.height + 3) / 4;
  const std::size_t count = s.etc1s_alpha ? 2 : 1;
  // ktx2_scan counted these against the limits (8 bytes a block at most).
  std::vector<detail::Etc1sBlock> blocks[2];
  std::string problems[2];
  try {
    for (std::size_t i = 0; i < count; ++i) blocks[i].resize(static_cast<std::size_t>(bw) * static_cast<std::size_t>(bh));
  } catch (const std::bad_alloc&) {
    detail::fail(name, where + "cannot decode (out of memory for its blocks)");
  }
  auto read = [&](std::size_t i) {
    problems[i] = detail::etc1s_decode_slice(g, slices[i], out.width, out.height, blocks[i]);
  };
  if (parallel && count > 1) parallel(count, read);
  else for (std::size_t i = 0; i < count; ++i) read(i);
  for (std::size_t i = 0; i < count; ++i)
    if (!problems[i].empty()) detail::fail(name, where + problems[i]);
  for_block_rows(bh, parallel, [&](std::size_t, int begin, int end) {
    detail::etc1s_expand(g, blocks[0], out.width, out.height, begin, end, out.rgba.data(), false);
    if (count > 1) detail::etc1s_expand(g, blocks[1], out.width, out.height, begin, end, out.rgba.data(), true);
  });
}

void decode_uastc(std::span<const std::uint8_t> data, Image8& out, int l, std::string_view name, const ParallelFor& parallel) {
  const int bw = (out.width + 3) / 4, bh = (out.height + 3) / 4;
  // ktx2_scan made the level exactly this long; checked again where the blocks are read.
  if (data.size() < static_cast<std::size_t>(bw) * static_cast<std::size_t>(bh) * 16)
    detail::fail(name, "level " + std::to_string(l) + ": its UASTC data is shorter than its blocks");
  // Each range's first bad block (bw · by + bx), or -1: the first range's is reported.
  std::vector<std::int64_t> bad(static_cast<std::size_t>((bh + kBlockRowsPerTask - 1) / kBlockRowsPerTask), -1);
  for_block_rows(bh, parallel, [&](std::size_t task, int begin, int end) {
    std::uint8_t texels[64];
    for (int by = begin; by < end; ++by)
      for (int bx = 0; bx < bw; ++bx) {
        const std::uint8_t* block = data.data() + (static_cast<std::size_t>(by) * bw + bx) * 16;
        if (!detail::decode_uastc_block(block, texels)) {
          bad[task] = std::int64_t(by) * bw + bx;
          return;
        }
        // The block's texels inside the level (a level's last blocks may overhang it).
        const int rows = std::min(4, out.height - by * 4), cols = std::min(4, out.width - bx * 4);
        for (int y = 0; y < rows; ++y)
          std::memcpy(&out.rgba[((static_cast<std::size_t>(by) * 4 + y) * out.width + bx * 4) * 4], texels + y * 16,
                      static_cast<std::size_t>(cols) * 4);
      }
  });
  for (const std::int64_t b : bad)
    if (b >= 0)
      detail::fail(name, "level " + std::to_string(l) + ": block (" + std::to_string(b % bw) + ", " + std::to_string(b / bw) +
                             ") is not a valid UASTC block");
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
                    std::string_view name, Capacity capacity, std::vector<std::uint8_t>& scratch,
                    const ParallelFor& parallel) {
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
  if (s.codec == detail::Ktx2Codec::Uastc) decode_uastc(data, out, l, name, parallel);
  else if (s.codec == detail::Ktx2Codec::Etc1s) decode_etc1s(data, s, g, out, l, name, parallel);
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

Ktx2Image load_ktx2(std::span<const std::uint8_t> bytes, std::string_view name, const Limits& limits, Capacity capacity,
                    const ParallelFor& parallel) {
  const detail::Ktx2Scan s = detail::ktx2_scan(bytes, name, limits, detail::kAllKtx2Levels);
  Ktx2Image out;
  out.info = s.info;
  const detail::Etc1sGlobal g = read_global(bytes, s, name);
  std::vector<std::uint8_t> scratch;
  for (int l = 0; l < static_cast<int>(s.levels.size()); ++l)
    out.levels.push_back(decode_level(bytes, s, g, l, name, l == 0 ? capacity : nullptr, scratch, parallel));
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
  return decode_level(bytes, s, g, 0, name, capacity, scratch, {});
}

}  // namespace softpbr::image
