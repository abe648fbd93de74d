// Image headers read without decoding (see load.h, read_image_header).
#include <limits>

#include "formats.h"
#include "jpeg_scan.h"
#include "softpbr/image/ktx2.h"
#include "softpbr/image/load.h"

namespace softpbr::image {

ImageHeader read_image_header(std::span<const std::uint8_t> bytes) {
  ImageHeader h;
  auto side = [](std::uint64_t v) { return v <= static_cast<std::uint64_t>(std::numeric_limits<int>::max()) ? static_cast<int>(v) : 0; };
  switch (detail::sniff(bytes)) {
    case detail::Format::Png: {
      h.format = "png";
      // ISO/IEC 15948 §5.3, §11.2.2: IHDR is the first chunk; width and height are its
      // first two big-endian 32-bit fields.
      if (bytes.size() >= 24 && bytes[12] == 'I' && bytes[13] == 'H' && bytes[14] == 'D' && bytes[15] == 'R') {
        auto be32 = [&](std::size_t at) {
          return (std::uint64_t{bytes[at]} << 24) | (std::uint64_t{bytes[at + 1]} << 16) |
                 (std::uint64_t{bytes[at + 2]} << 8) | std::uint64_t{bytes[at + 3]};
        };
        h.width = side(be32(16));
        h.height = side(be32(20));
        if (h.width == 0 || h.height == 0) h.width = h.height = 0;
      }
      break;
    }
    case detail::Format::Jpeg: {
      h.format = "jpeg";
      const detail::JpegScan scan = detail::jpeg_scan(bytes);
      h.width = scan.width;
      h.height = scan.height;
      break;
    }
    case detail::Format::Hdr: h.format = "hdr"; break;
    case detail::Format::Exr: h.format = "exr"; break;
    case detail::Format::Ktx2: {
      h.format = "ktx2";
      const Ktx2Info k = read_ktx2_info(bytes);
      if (k.format.empty()) break;  // a truncated header
      h.width = k.width;
      h.height = k.height;
      h.detail = k.format + ", " + (k.supercompression.empty() ? "unknown supercompression" : k.supercompression) +
                 ", " + std::to_string(k.levels) + (k.levels == 1 ? " level" : " levels") + (k.srgb ? ", sRGB" : ", linear");
      break;
    }
    case detail::Format::Webp:
      h.format = "webp";
      if (!detail::webp_size(bytes, h.width, h.height)) h.width = h.height = 0;
      break;
    case detail::Format::Avif:
      h.format = "avif";
      if (!detail::avif_size(bytes, h.width, h.height)) h.width = h.height = 0;
      break;
    default: break;
  }
  return h;
}

}  // namespace softpbr::image
