// The shared calls into stb_image (see stb_decode.h).
#include "stb_decode.h"

#include <string>

#include <stb_image.h>

#include "formats.h"

namespace softpbr::image::detail {

void StbFree::operator()(void* p) const { stbi_image_free(p); }

StbSize stb_info(std::span<const std::uint8_t> bytes, std::string_view name) {
  StbSize size;
  int channels = 0;
  if (!stbi_info_from_memory(bytes.data(), stb_size(bytes, name), &size.width, &size.height, &channels))
    fail(name, std::string("not a readable image (") + stbi_failure_reason() + ")");
  return size;
}

Image8 stb_load_rgba8(std::span<const std::uint8_t> bytes, std::string_view name) {
  int w = 0, h = 0, channels = 0;
  const StbPixels<stbi_uc> data(stbi_load_from_memory(bytes.data(), stb_size(bytes, name), &w, &h, &channels, 4));
  if (!data) fail(name, std::string("cannot decode (") + stbi_failure_reason() + ")");
  Image8 image{w, h, {}};
  image.rgba.assign(data.get(), data.get() + static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * 4);
  return image;
}

}  // namespace softpbr::image::detail
