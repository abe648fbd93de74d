// The shared calls into stb_image and stb_image_write (see stb_decode.h), and both
// themselves: their implementations (Debian's libstb-dev headers) compiled here, with the
// project's flags and static, so no other copy in the process can take their place. Linking libstb.so instead
// left the choice to the dynamic linker: libdraco.so exports the copy of stb_image it
// bundles, and as it came first in the link line, that copy decoded every image.
#include "stb_decode.h"

#include <algorithm>
#include <string>

#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wsign-compare"
#pragma GCC diagnostic ignored "-Wunused-parameter"
#pragma GCC diagnostic ignored "-Wimplicit-fallthrough"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wtype-limits"
#pragma GCC diagnostic ignored "-Wunused-but-set-variable"
#endif
#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#include <stb_image.h>
#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb_image_write.h>
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

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

Image8 stb_load_rgba8(std::span<const std::uint8_t> bytes, std::string_view name, Capacity capacity) {
  int w = 0, h = 0, channels = 0;
  const std::unique_ptr<stbi_uc[], StbFree> data(stbi_load_from_memory(bytes.data(), stb_size(bytes, name), &w, &h, &channels, 4));
  if (!data) fail(name, std::string("cannot decode (") + stbi_failure_reason() + ")");
  Image8 image{w, h, {}};
  const std::size_t size = static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * 4;
  if (capacity != nullptr) image.rgba.reserve(std::max(size, capacity(w, h)));
  image.rgba.assign(data.get(), data.get() + size);
  return image;
}

std::unique_ptr<float[], StbFree> stb_load_rgb_float(std::span<const std::uint8_t> bytes, std::string_view name,
                                                     int& width, int& height) {
  int channels = 0;
  std::unique_ptr<float[], StbFree> rgb(
      stbi_loadf_from_memory(bytes.data(), stb_size(bytes, name), &width, &height, &channels, 3));
  if (!rgb) fail(name, std::string("cannot decode (") + stbi_failure_reason() + ")");
  return rgb;
}

std::vector<std::uint8_t> stb_encode_hdr(std::span<const float> rgb, int width, int height, std::string_view name) {
  std::vector<std::uint8_t> bytes;
  if (!stbi_write_hdr_to_func(append_bytes, &bytes, width, height, 3, rgb.data())) fail(name, "HDR encoding failed");
  return bytes;
}

}  // namespace softpbr::image::detail
