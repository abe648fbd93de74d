// PNG through libspng: loading (after png_scan.h's chunk walk and the size check) and
// writing.
#include <algorithm>
#include <cstdlib>
#include <memory>
#include <new>
#include <string>
#include <vector>

#include <spng.h>

#include "formats.h"
#include "png_scan.h"
#include "softpbr/image/load.h"
#include "softpbr/image/write.h"

namespace softpbr::image {

namespace {
using SpngContext = std::unique_ptr<spng_ctx, decltype(&spng_ctx_free)>;

// libspng decodes into the image's own buffer, to 8-bit RGBA: palette and grey expanded,
// tRNS applied, 16-bit samples reduced to their high byte — what stb_image did (it decoded
// PNGs before; the tests compare both on every kind of PNG), about 1.3× faster and with
// no copy of the pixels. As stb_image, it reads past bad CRCs and zlib checksums; gamma
// and colour chunks are not applied (glTF and scene textures are sRGB or linear data).
// The file with only the chunks the pixels need: the critical ones (IHDR, PLTE, IDAT, IEND,
// and any unknown critical chunk, which libspng refuses) and tRNS. libspng keeps every
// text, colour and other ancillary chunk it meets in memory, within chunk and cache limits
// it then refuses the file for ("reached chunk/cache limits": a valid PNG with a few
// thousand tEXt chunks); none of them changes the pixels softpbr decodes (gamma and colour
// chunks are not applied). `bytes` itself when there is nothing to drop; the walk runs
// after png_truncation, so every chunk lies inside the file.
std::span<const std::uint8_t> pixel_chunks(std::span<const std::uint8_t> bytes, std::vector<std::uint8_t>& storage) {
  auto chunk_end = [&](std::size_t at) {
    const std::uint32_t length = (std::uint32_t{bytes[at]} << 24) | (std::uint32_t{bytes[at + 1]} << 16) |
                                 (std::uint32_t{bytes[at + 2]} << 8) | std::uint32_t{bytes[at + 3]};
    return std::min(bytes.size(), at + 12 + std::size_t{length});
  };
  // PNG §5.4: bit 5 of a chunk type's first byte (a lower-case letter) marks it ancillary.
  auto kept = [&](std::size_t at) {
    const bool ancillary = (bytes[at + 4] & 0x20) != 0;
    return !ancillary || (bytes[at + 4] == 't' && bytes[at + 5] == 'R' && bytes[at + 6] == 'N' && bytes[at + 7] == 'S');
  };
  std::size_t dropped = 0;
  for (std::size_t at = 8; at + 12 <= bytes.size(); at = chunk_end(at))
    if (!kept(at)) ++dropped;
  if (dropped == 0) return bytes;
  storage.reserve(bytes.size());
  storage.assign(bytes.begin(), bytes.begin() + 8);
  std::size_t at = 8;
  for (; at + 12 <= bytes.size(); at = chunk_end(at))
    if (kept(at)) storage.insert(storage.end(), bytes.begin() + static_cast<std::ptrdiff_t>(at),
                                 bytes.begin() + static_cast<std::ptrdiff_t>(chunk_end(at)));
  storage.insert(storage.end(), bytes.begin() + static_cast<std::ptrdiff_t>(std::min(at, bytes.size())), bytes.end());
  return storage;
}

// libspng set up over a file's pixel chunks (pixel_chunks: `storage` holds them when
// ancillary ones were dropped) with the image limits and CRC checks, its header read: `e`
// is libspng's first error (0: none), as the decoders below go on with it.
struct SpngDecoder {
  std::vector<std::uint8_t> storage;
  SpngContext ctx{nullptr, &spng_ctx_free};
  int e = 0;
  spng_ihdr ihdr{};

  SpngDecoder(std::span<const std::uint8_t> file, std::string_view name, const Limits& limits) {
    const std::span<const std::uint8_t> bytes = pixel_chunks(file, storage);
    ctx.reset(spng_ctx_new(SPNG_CTX_IGNORE_ADLER32));
    if (!ctx) detail::fail(name, "cannot decode (out of memory)");
    const auto side = static_cast<std::uint32_t>(std::max(limits.max_side, 1));
    e = spng_set_image_limits(ctx.get(), side, side);
    if (!e) e = spng_set_chunk_limits(ctx.get(), bytes.size(), bytes.size());
    if (!e) e = spng_set_crc_action(ctx.get(), SPNG_CRC_USE, SPNG_CRC_USE);
    if (!e) e = spng_set_png_buffer(ctx.get(), bytes.data(), bytes.size());
    if (!e) e = spng_get_ihdr(ctx.get(), &ihdr);
  }
};

Image8 decode_png(std::span<const std::uint8_t> file, std::string_view name, const Limits& limits, Capacity capacity) {
  SpngDecoder d(file, name, limits);
  const SpngContext& ctx = d.ctx;
  int& e = d.e;
  const spng_ihdr& ihdr = d.ihdr;  // its size was checked against `limits` by load_png
  std::size_t size = 0;
  if (!e) e = spng_decoded_image_size(ctx.get(), SPNG_FMT_RGBA8, &size);
  Image8 image;
  if (!e) {
    image.width = static_cast<int>(ihdr.width);
    image.height = static_cast<int>(ihdr.height);
    try {
      if (capacity != nullptr) image.rgba.reserve(std::max(size, capacity(image.width, image.height)));
      image.rgba.resize(size);
    } catch (const std::bad_alloc&) {  // a process or address-space limit: as stb_image said it
      detail::fail(name, "cannot decode (out of memory for " + std::to_string(size) + " bytes of pixels)");
    }
    e = spng_decode_image(ctx.get(), image.rgba.data(), size, SPNG_FMT_RGBA8, SPNG_DECODE_TRNS);
  }
  if (e) detail::fail(name, std::string("cannot decode (") + spng_strerror(e) + ")");
  return image;
}
}  // namespace

Image8 load_png(std::span<const std::uint8_t> bytes, std::string_view name, const Limits& limits) {
  return detail::png_rgba8(bytes, name, limits, nullptr);
}

Image8 detail::png_rgba8(std::span<const std::uint8_t> bytes, std::string_view name, const Limits& limits,
                         Capacity capacity) {
  detail::expect_format(bytes, name, detail::Format::Png);
  // The size from the IHDR chunk (it must follow the signature), before anything else.
  if (bytes.size() >= 24 && bytes[12] == 'I' && bytes[13] == 'H' && bytes[14] == 'D' && bytes[15] == 'R') {
    auto be32 = [&](std::size_t at) {
      return (std::uint32_t{bytes[at]} << 24) | (std::uint32_t{bytes[at + 1]} << 16) | (std::uint32_t{bytes[at + 2]} << 8) |
             std::uint32_t{bytes[at + 3]};
    };
    detail::check_size(name, be32(16), be32(20), 4, limits);
  }
  // Decoders allocate what a chunk claims before reading it (png_scan.h).
  if (const std::string problem = detail::png_truncation(bytes); !problem.empty())
    detail::fail(name, "cannot decode (" + problem + ")");
  return decode_png(bytes, name, limits, capacity);
}

ImageF load_png16(std::span<const std::uint8_t> file, std::string_view name, const Limits& limits) {
  detail::expect_format(file, name, detail::Format::Png);
  // As png_rgba8: the header's size first (8 bytes a pixel at 16 bits, then 16 as floats),
  // the chunk walk, the pixels' chunks alone.
  if (file.size() >= 24 && file[12] == 'I' && file[13] == 'H' && file[14] == 'D' && file[15] == 'R') {
    auto be32 = [&](std::size_t at) {
      return (std::uint32_t{file[at]} << 24) | (std::uint32_t{file[at + 1]} << 16) | (std::uint32_t{file[at + 2]} << 8) |
             std::uint32_t{file[at + 3]};
    };
    detail::check_size(name, be32(16), be32(20), 8 + 16, limits);
  }
  if (const std::string problem = detail::png_truncation(file); !problem.empty())
    detail::fail(name, "cannot decode (" + problem + ")");
  SpngDecoder d(file, name, limits);
  const SpngContext& ctx = d.ctx;
  int& e = d.e;
  const spng_ihdr& ihdr = d.ihdr;
  std::size_t size = 0;
  if (!e) e = spng_decoded_image_size(ctx.get(), SPNG_FMT_RGBA16, &size);
  ImageF image;
  if (!e) {
    std::vector<std::uint16_t> samples;
    try {
      samples.resize(size / 2);
      image.rgba.resize(size / 2);
    } catch (const std::bad_alloc&) {
      detail::fail(name, "cannot decode (out of memory for " + std::to_string(size * 3) + " bytes of pixels)");
    }
    e = spng_decode_image(ctx.get(), samples.data(), size, SPNG_FMT_RGBA16, SPNG_DECODE_TRNS);
    if (!e) {
      image.width = static_cast<int>(ihdr.width);
      image.height = static_cast<int>(ihdr.height);
      // libspng widens lower depths itself (8-bit 255 to 65535, ISO/IEC 15948 §13.12).
      for (std::size_t i = 0; i < samples.size(); ++i) image.rgba[i] = static_cast<float>(samples[i]);
    }
  }
  if (e) detail::fail(name, std::string("cannot decode (") + spng_strerror(e) + ")");
  return image;
}

Image8 load_png(const std::filesystem::path& path, const Limits& limits) {
  return load_png(detail::read_file(path, limits), path.string(), limits);
}

std::vector<std::uint8_t> encode_png(const ImageView8& image, std::string_view name) {
  detail::check_writable(image, name);
  // libspng with zlib at level 2 and the Sub filter on every row: at 1920×1080 about a
  // fifth of the time stb_image_write took (level 8, all five filters tried per row) for
  // files 5–15% smaller on renders (docs/design.md, "Images"). The bytes depend on libspng
  // and zlib's versions; the pixels never do.
  const std::unique_ptr<spng_ctx, decltype(&spng_ctx_free)> ctx(spng_ctx_new(SPNG_CTX_ENCODER), &spng_ctx_free);
  if (!ctx) detail::fail(name, "PNG encoding failed (out of memory)");
  spng_ihdr ihdr{};
  ihdr.width = static_cast<std::uint32_t>(image.width);
  ihdr.height = static_cast<std::uint32_t>(image.height);
  ihdr.bit_depth = 8;
  ihdr.color_type = SPNG_COLOR_TYPE_TRUECOLOR_ALPHA;
  int e = spng_set_option(ctx.get(), SPNG_ENCODE_TO_BUFFER, 1);
  if (!e) e = spng_set_ihdr(ctx.get(), &ihdr);
  if (!e) e = spng_set_option(ctx.get(), SPNG_IMG_COMPRESSION_LEVEL, 2);
  if (!e) e = spng_set_option(ctx.get(), SPNG_FILTER_CHOICE, SPNG_FILTER_CHOICE_SUB);
  if (!e)
    e = spng_encode_image(ctx.get(), image.rgba.data(), image.rgba.size(), SPNG_FMT_PNG, SPNG_ENCODE_FINALIZE);
  std::size_t size = 0;
  void* const bytes = e ? nullptr : spng_get_png_buffer(ctx.get(), &size, &e);
  if (!bytes) detail::fail(name, std::string("PNG encoding failed (") + spng_strerror(e) + ")");
  const std::unique_ptr<void, decltype(&std::free)> owned(bytes, &std::free);
  const auto* first = static_cast<const std::uint8_t*>(bytes);
  return std::vector<std::uint8_t>(first, first + size);
}

void write_png(const std::filesystem::path& path, const ImageView8& image) {
  write_file_atomic(path, encode_png(image, path.string()));
}

}  // namespace softpbr::image
