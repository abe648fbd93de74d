// JPEG through stb_image, after jpeg_scan.h's marker walk.
#include <string>

#include "formats.h"
#include "jpeg_scan.h"
#include "softpbr/image/load.h"
#include "stb_decode.h"

namespace softpbr::image {

Image8 load_jpeg(std::span<const std::uint8_t> bytes, std::string_view name, const Limits& limits) {
  return detail::jpeg_rgba8(bytes, name, limits, nullptr);
}

Image8 detail::jpeg_rgba8(std::span<const std::uint8_t> bytes, std::string_view name, const Limits& limits,
                          Capacity capacity) {
  detail::expect_format(bytes, name, detail::Format::Jpeg);
  const detail::JpegScan scan = detail::jpeg_scan(bytes);
  // The size first when the frame header was read: the more useful message for a file
  // that claims too much and also lacks the data.
  if (scan.width > 0)
    detail::check_size(name, scan.width, scan.height, 4, limits, scan.plane_samples * (scan.progressive ? 3 : 1));
  if (!scan.problem.empty()) detail::fail(name, "cannot decode (" + scan.problem + ")");
  const detail::StbSize size = detail::stb_info(bytes, name);
  if (size.width != scan.width || size.height != scan.height)
    detail::fail(name, "not a readable image (stb_image reads its size as " + std::to_string(size.width) + "x" +
                           std::to_string(size.height) + ", the frame header says " + std::to_string(scan.width) +
                           "x" + std::to_string(scan.height) + ")");
  return detail::stb_load_rgba8(bytes, name, capacity);
}

Image8 load_jpeg(const std::filesystem::path& path, const Limits& limits) {
  return load_jpeg(detail::read_file(path, limits), path.string(), limits);
}

}  // namespace softpbr::image
