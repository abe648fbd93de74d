// PNG through stb_image (loading, after png_scan.h's chunk walk) and stb_image_write.
#include <string>

#include <stb_image_write.h>

#include "formats.h"
#include "png_scan.h"
#include "softpbr/image/load.h"
#include "softpbr/image/write.h"
#include "stb_decode.h"

namespace softpbr::image {

Image8 load_png(std::span<const std::uint8_t> bytes, std::string_view name, const Limits& limits) {
  detail::expect_format(bytes, name, detail::Format::Png);
  // The size from the IHDR chunk first (it must follow the signature): stb_info refuses an
  // image over 2^30 pixel bytes as "unknown image type", which would hide the reason.
  if (bytes.size() >= 24 && bytes[12] == 'I' && bytes[13] == 'H' && bytes[14] == 'D' && bytes[15] == 'R') {
    auto be32 = [&](std::size_t at) {
      return (std::uint32_t{bytes[at]} << 24) | (std::uint32_t{bytes[at + 1]} << 16) | (std::uint32_t{bytes[at + 2]} << 8) |
             std::uint32_t{bytes[at + 3]};
    };
    detail::check_size(name, be32(16), be32(20), 4, limits);
  }
  const detail::StbSize size = detail::stb_info(bytes, name);
  detail::check_size(name, size.width, size.height, 4, limits);
  // stb_image allocates what a chunk claims before reading it (png_scan.h).
  if (const std::string problem = detail::png_truncation(bytes); !problem.empty())
    detail::fail(name, "cannot decode (" + problem + ")");
  return detail::stb_load_rgba8(bytes, name);
}

Image8 load_png(const std::filesystem::path& path, const Limits& limits) {
  return load_png(detail::read_file(path, limits), path.string(), limits);
}

std::vector<std::uint8_t> encode_png(const ImageView8& image, std::string_view name) {
  detail::check_writable(image, name);
  std::vector<std::uint8_t> png;
  if (!stbi_write_png_to_func(detail::append_bytes, &png, image.width, image.height, 4, image.rgba.data(),
                              image.width * 4))
    detail::fail(name, "PNG encoding failed");
  return png;
}

void write_png(const std::filesystem::path& path, const ImageView8& image) {
  write_file_atomic(path, encode_png(image, path.string()));
}

}  // namespace softpbr::image
