// What the format files share (see formats.h).
#include "formats.h"
#include "softpbr/image/load.h"
#include "softpbr/image/read_file.h"

#include <algorithm>
#include <climits>
#include <stdexcept>
#include <system_error>

namespace softpbr::image::detail {

void fail(std::string_view name, std::string_view what) {
  std::string message(name);
  message += ": ";
  message += what;
  throw std::runtime_error(message);
}

namespace {
bool starts_with(std::span<const std::uint8_t> bytes, std::string_view magic) {
  return bytes.size() >= magic.size() && std::equal(magic.begin(), magic.end(), bytes.begin(), [](char m, std::uint8_t b) {
           return static_cast<std::uint8_t>(m) == b;
         });
}

// ISO/IEC 14496-12 §4.3: the first box, "ftyp", holds the major brand and then the
// compatible brands up to its size (read as far as the file goes: a cut file is still an
// AVIF, whose decoder then says it is cut). MIAF/AVIF brands: "avif" (still image), "avis"
// (sequence).
bool is_avif(std::span<const std::uint8_t> bytes) {
  using namespace std::string_view_literals;
  if (bytes.size() < 12 || !starts_with(bytes.subspan(4), "ftyp"sv)) return false;
  const std::uint64_t box = (std::uint64_t{bytes[0]} << 24) | (std::uint64_t{bytes[1]} << 16) |
                            (std::uint64_t{bytes[2]} << 8) | std::uint64_t{bytes[3]};
  const std::size_t end = static_cast<std::size_t>(std::min<std::uint64_t>(box < 16 ? 12 : box, bytes.size()));
  for (std::size_t at = 8; at + 4 <= end; at += at == 8 ? 8 : 4)  // the major brand, then (after minor_version) the compatible ones
    if (starts_with(bytes.subspan(at), "avif"sv) || starts_with(bytes.subspan(at), "avis"sv)) return true;
  return false;
}

const char* loader_of(Format f) {
  switch (f) {
    case Format::Png: return "load_png";
    case Format::Jpeg: return "load_jpeg";
    case Format::Hdr: return "load_hdr";
    case Format::Ktx2: return "load_ktx2";
    case Format::Webp: return "load_webp";
    case Format::Avif: return "load_avif";
    default: return "load_exr";
  }
}
}  // namespace

Format sniff(std::span<const std::uint8_t> bytes) {
  using namespace std::string_view_literals;
  if (starts_with(bytes, "\x89PNG\r\n\x1a\n"sv)) return Format::Png;
  if (starts_with(bytes, "\xff\xd8\xff"sv)) return Format::Jpeg;
  if (starts_with(bytes, "#?RADIANCE\n"sv) || starts_with(bytes, "#?RGBE\n"sv)) return Format::Hdr;
  if (starts_with(bytes, "\x76\x2f\x31\x01"sv)) return Format::Exr;
  if (starts_with(bytes, "\xabKTX 20\xbb\r\n\x1a\n"sv)) return Format::Ktx2;
  if (starts_with(bytes, "RIFF"sv) && starts_with(bytes.subspan(std::min<std::size_t>(8, bytes.size())), "WEBP"sv))
    return Format::Webp;
  if (is_avif(bytes)) return Format::Avif;
  return Format::Unknown;
}

void expect_format(std::span<const std::uint8_t> bytes, std::string_view name, Format wanted) {
  const Format found = sniff(bytes);
  if (found == wanted) return;
  const bool wanted_float = wanted == Format::Hdr || wanted == Format::Exr;
  switch (found) {
    case Format::Png:
    case Format::Jpeg:
      if (wanted_float)
        fail(name, std::string("is an 8-bit image, not a ") + (wanted == Format::Hdr ? "Radiance .hdr" : "OpenEXR") +
                       " image; load it with " + loader_of(found));
      fail(name, std::string("is a ") + (found == Format::Png ? "PNG" : "JPEG") + " image; load it with " +
                     loader_of(found) + " (or load_image8)");
    case Format::Hdr:
    case Format::Exr:
      if (!wanted_float)
        fail(name, std::string("is a ") + (found == Format::Hdr ? "Radiance .hdr" : "OpenEXR") +
                       " (float) image; load it with " + loader_of(found));
      fail(name, std::string("is a ") + (found == Format::Hdr ? "Radiance .hdr" : "OpenEXR") + " image; load it with " +
                     loader_of(found) + " (or load_imagef)");
    case Format::Ktx2:
      if (wanted_float) fail(name, "is a KTX2 (8-bit) texture, not a float image; load it with load_ktx2 or load_image8");
      fail(name, "is a KTX2 texture; load it with load_ktx2 (or load_image8)");
    case Format::Webp:
    case Format::Avif: {
      const char* what = found == Format::Webp ? "WebP" : "AVIF";
      if (wanted_float)
        fail(name, std::string("is a ") + what + " (8-bit) image, not a float image; load it with " + loader_of(found) +
                       " or load_image8");
      fail(name, std::string("is a ") + what + " image; load it with " + loader_of(found) + " (or load_image8)");
    }
    default: {
      const char* what = wanted == Format::Png    ? "PNG"
                         : wanted == Format::Jpeg ? "JPEG"
                         : wanted == Format::Webp ? "WebP"
                         : wanted == Format::Avif ? "AVIF"
                         : wanted == Format::Hdr  ? "Radiance .hdr"
                                                  : "OpenEXR";
      fail(name, std::string("not a readable image (no ") + what + " signature)");
    }
  }
}

void check_size(std::string_view name, std::int64_t width, std::int64_t height, std::uint64_t bytes_per_pixel,
                const Limits& limits, std::uint64_t extra_bytes) {
  const std::int64_t side = std::clamp(limits.max_side, 1, kMaxSide);
  if (width < 1 || height < 1 || width > side || height > side)
    fail(name, "image size " + std::to_string(width) + "x" + std::to_string(height) + " is outside 1x1 .. " +
                   std::to_string(side) + "x" + std::to_string(side));
  // At most 16384² × (16 + 4 × channels) here, far inside 64 bits for any channel count tinyexr parses.
  const std::uint64_t pixels = static_cast<std::uint64_t>(width) * static_cast<std::uint64_t>(height);
  const std::uint64_t bytes = pixels * bytes_per_pixel + extra_bytes;
  if (bytes > limits.max_decoded_bytes)
    fail(name, "image size " + std::to_string(width) + "x" + std::to_string(height) + " needs " + std::to_string(bytes) +
                   " bytes decoded, over the limit of " + std::to_string(limits.max_decoded_bytes));
}

int stb_size(std::span<const std::uint8_t> bytes, std::string_view name) {
  if (bytes.size() > static_cast<std::size_t>(INT_MAX)) fail(name, "over 2 GiB, more than the decoder reads");
  return static_cast<int>(bytes.size());
}

std::vector<std::uint8_t> read_file(const std::filesystem::path& path, const Limits& limits) {
  std::vector<std::uint8_t> bytes;
  if (const FileProblem p = read_whole_file(path, limits.max_file_bytes, bytes))
    fail(path.string(), p.folder ? "is a folder, not an image" : p.reason);
  return bytes;
}

}  // namespace softpbr::image::detail

namespace softpbr::image {
std::vector<std::uint8_t> read_file(const std::filesystem::path& path, const Limits& limits) {
  return detail::read_file(path, limits);
}
}  // namespace softpbr::image

namespace softpbr::image::detail {

namespace {
template <class Sample>
void check_encodable(const ImageView<Sample>& image, std::string_view name) {
  check_pixels(image, name);
  if (image.width < 1 || image.height < 1) throw std::invalid_argument(std::string(name) + ": cannot write an empty image");
}
}  // namespace

void check_writable(const ImageView8& image, std::string_view name) { check_encodable(image, name); }
void check_writable(const ImageViewF& image, std::string_view name) { check_encodable(image, name); }

void append_bytes(void* context, void* data, int size) {
  auto* out = static_cast<std::vector<std::uint8_t>*>(context);
  const auto* bytes = static_cast<const std::uint8_t*>(data);
  out->insert(out->end(), bytes, bytes + size);
}

}  // namespace softpbr::image::detail
