// What RGBE storage does to float values, and the conversions between images and render
// targets (see image.h). Loading and writing are softpbr::image's.
#include "softpbr/golden/image.h"

#include <cstdint>
#include <limits>

#include "softpbr/raster/color.h"

namespace softpbr::golden {

ImageF hdr_round_trip(const ImageF& image) {
  // Any size an image may have: this is data in memory, not a file from elsewhere.
  image::Limits any_size;
  any_size.max_decoded_bytes = std::numeric_limits<std::uint64_t>::max();
  return image::load_hdr(image::encode_hdr(image, "hdr_round_trip"), "hdr_round_trip", any_size);
}

ImageF to_image(const raster::Target& target) {
  ImageF image{target.width(), target.height(), {}};
  image.rgba.reserve(target.colors().size() * 4);
  for (const glm::vec4& c : target.colors()) image.rgba.insert(image.rgba.end(), {c.r, c.g, c.b, c.a});
  return image;
}

ImageF to_float(const Image8& image) {
  ImageF out{image.width, image.height, {}};
  out.rgba.reserve(image.rgba.size());
  for (std::uint8_t code : image.rgba) out.rgba.push_back(static_cast<float>(code) / 255.0f);
  return out;
}

Image8 to_srgb8(const ImageF& image) {
  image::check_pixels(image, "to_srgb8");
  Image8 out{image.width, image.height, {}};
  out.rgba.resize(image.rgba.size());
  for (std::size_t i = 0; i < image.rgba.size(); i += 4) {
    out.rgba[i + 0] = raster::linear_to_srgb8(image.rgba[i + 0]);
    out.rgba[i + 1] = raster::linear_to_srgb8(image.rgba[i + 1]);
    out.rgba[i + 2] = raster::linear_to_srgb8(image.rgba[i + 2]);
    out.rgba[i + 3] = raster::unorm8(image.rgba[i + 3]);
  }
  return out;
}

}  // namespace softpbr::golden
