// Radiance .hdr through stb_image (loading, after hdr_scan.h's walk over the pixel data) and
// stb_image_write (RGBE, run-length encoded).
#include <cmath>
#include <string>

#include "formats.h"
#include "hdr_scan.h"
#include "softpbr/image/load.h"
#include "softpbr/image/write.h"
#include "stb_decode.h"

namespace softpbr::image {

ImageF load_hdr(std::span<const std::uint8_t> bytes, std::string_view name, const Limits& limits) {
  detail::expect_format(bytes, name, detail::Format::Hdr);
  const detail::StbSize size = detail::stb_info(bytes, name);
  detail::check_size(name, size.width, size.height, 16, limits);
  // stb_image hangs on some truncated files (hdr_scan.h): check the data is all there.
  if (const std::string problem = detail::hdr_truncation(bytes, size.width, size.height); !problem.empty())
    detail::fail(name, problem);
  int w = 0, h = 0;
  const auto rgb = detail::stb_load_rgb_float(bytes, name, w, h);
  ImageF image{w, h, {}};
  const std::size_t n = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
  image.rgba.resize(n * 4);
  for (std::size_t i = 0; i < n; ++i) {
    image.rgba[4 * i + 0] = rgb.get()[3 * i + 0];
    image.rgba[4 * i + 1] = rgb.get()[3 * i + 1];
    image.rgba[4 * i + 2] = rgb.get()[3 * i + 2];
    image.rgba[4 * i + 3] = 1.0f;
  }
  return image;
}

ImageF load_hdr(const std::filesystem::path& path, const Limits& limits) {
  return load_hdr(detail::read_file(path, limits), path.string(), limits);
}

std::vector<std::uint8_t> encode_hdr(const ImageViewF& image, std::string_view name, float scale) {
  detail::check_writable(image, name);
  // RGBE cannot hold negative or non-finite values: they are stored as 0.
  std::vector<float> rgb;
  rgb.reserve(image.rgba.size() / 4 * 3);
  for (std::size_t i = 0; i < image.rgba.size(); i += 4)
    for (std::size_t c = 0; c < 3; ++c) {
      const float v = image.rgba[i + c];
      const float scaled = std::isfinite(v) ? v * scale : 0.0f;
      rgb.push_back(std::isfinite(scaled) && scaled > 0.0f ? scaled : 0.0f);
    }
  return detail::stb_encode_hdr(rgb, image.width, image.height, name);
}

void write_hdr(const std::filesystem::path& path, const ImageViewF& image, float scale) {
  write_file_atomic(path, encode_hdr(image, path.string(), scale));
}

}  // namespace softpbr::image
