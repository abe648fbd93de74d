// JPEG through stb_image, after jpeg_scan.h's marker walk.
#include <string>

#include <stb_image.h>

#include "formats.h"
#include "jpeg_scan.h"
#include "softpbr/image/load.h"
#include "stb_owner.h"

namespace softpbr::image {

Image8 load_jpeg(std::span<const std::uint8_t> bytes, std::string_view name, const Limits& limits) {
  detail::expect_format(bytes, name, detail::Format::Jpeg);
  const int size = detail::stb_size(bytes, name);
  const detail::JpegScan scan = detail::jpeg_scan(bytes);
  // The size first when the frame header was read: the more useful message for a file
  // that claims too much and also lacks the data.
  if (scan.width > 0)
    detail::check_size(name, scan.width, scan.height, 4, limits, scan.plane_samples * (scan.progressive ? 3 : 1));
  if (!scan.problem.empty()) detail::fail(name, "cannot decode (" + scan.problem + ")");
  int w = 0, h = 0, channels = 0;
  if (!stbi_info_from_memory(bytes.data(), size, &w, &h, &channels))
    detail::fail(name, std::string("not a readable image (") + stbi_failure_reason() + ")");
  if (w != scan.width || h != scan.height)
    detail::fail(name, "not a readable image (stb_image reads its size as " + std::to_string(w) + "x" +
                           std::to_string(h) + ", the frame header says " + std::to_string(scan.width) + "x" +
                           std::to_string(scan.height) + ")");
  const detail::StbPixels<stbi_uc> data(stbi_load_from_memory(bytes.data(), size, &w, &h, &channels, 4));
  if (!data) detail::fail(name, std::string("cannot decode (") + stbi_failure_reason() + ")");
  Image8 image{w, h, {}};
  image.rgba.assign(data.get(), data.get() + static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * 4);
  return image;
}

Image8 load_jpeg(const std::filesystem::path& path, const Limits& limits) {
  return load_jpeg(detail::read_file(path, limits), path.string(), limits);
}

}  // namespace softpbr::image
