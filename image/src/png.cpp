// PNG through stb_image (loading, after png_scan.h's chunk walk) and stb_image_write.
#include <string>

#include <stb_image.h>
#include <stb_image_write.h>

#include "formats.h"
#include "png_scan.h"
#include "softpbr/image/load.h"
#include "softpbr/image/write.h"
#include "stb_owner.h"

namespace softpbr::image {

Image8 load_png(std::span<const std::uint8_t> bytes, std::string_view name, const Limits& limits) {
  detail::expect_format(bytes, name, detail::Format::Png);
  const int size = detail::stb_size(bytes, name);
  int w = 0, h = 0, channels = 0;
  if (!stbi_info_from_memory(bytes.data(), size, &w, &h, &channels))
    detail::fail(name, std::string("not a readable image (") + stbi_failure_reason() + ")");
  detail::check_size(name, w, h, 4, limits);
  // stb_image allocates what a chunk claims before reading it (png_scan.h).
  if (const std::string problem = detail::png_truncation(bytes); !problem.empty())
    detail::fail(name, "cannot decode (" + problem + ")");
  const detail::StbPixels<stbi_uc> data(stbi_load_from_memory(bytes.data(), size, &w, &h, &channels, 4));
  if (!data) detail::fail(name, std::string("cannot decode (") + stbi_failure_reason() + ")");
  Image8 image{w, h, {}};
  image.rgba.assign(data.get(), data.get() + static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * 4);
  return image;
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
