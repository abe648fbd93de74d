// The loaders that choose a format by the first bytes (see load.h).
#include "formats.h"
#include "softpbr/image/load.h"

namespace softpbr::image {

Image8 load_image8(std::span<const std::uint8_t> bytes, std::string_view name, const Limits& limits) {
  return load_image8(bytes, name, limits, nullptr);
}

Image8 load_image8(std::span<const std::uint8_t> bytes, std::string_view name, const Limits& limits, Capacity capacity) {
  switch (detail::sniff(bytes)) {
    case detail::Format::Jpeg: return detail::jpeg_rgba8(bytes, name, limits, capacity);
    case detail::Format::Png: return detail::png_rgba8(bytes, name, limits, capacity);
    case detail::Format::Ktx2: return detail::ktx2_rgba8(bytes, name, limits, capacity);
    case detail::Format::Webp: return detail::webp_rgba8(bytes, name, limits, capacity);
    case detail::Format::Avif: return detail::avif_rgba8(bytes, name, limits, capacity);
    case detail::Format::Hdr: detail::fail(name, "is a Radiance .hdr (float) image; load it with load_hdr (or load_imagef)");
    case detail::Format::Exr: detail::fail(name, "is an OpenEXR (float) image; load it with load_exr (or load_imagef)");
    default: detail::fail(name, "not a readable image (no PNG, JPEG, KTX2, WebP or AVIF signature)");
  }
}

Image8 load_image8(const std::filesystem::path& path, const Limits& limits) {
  return load_image8(detail::read_file(path, limits), path.string(), limits);
}

ImageF load_imagef(std::span<const std::uint8_t> bytes, std::string_view name, const Limits& limits) {
  switch (detail::sniff(bytes)) {
    case detail::Format::Hdr: return load_hdr(bytes, name, limits);
    case detail::Format::Exr: return load_exr(bytes, name, limits);
    case detail::Format::Png:
    case detail::Format::Jpeg:
    case detail::Format::Ktx2:
    case detail::Format::Webp:
    case detail::Format::Avif: detail::fail(name, "is an 8-bit image; load it with load_image8");
    default: detail::fail(name, "not a readable image (no Radiance .hdr or OpenEXR signature)");
  }
}

ImageF load_imagef(const std::filesystem::path& path, const Limits& limits) {
  return load_imagef(detail::read_file(path, limits), path.string(), limits);
}

}  // namespace softpbr::image
