// The chunk-length check of PNG files (see png_scan.h). Layout (PNG spec, ISO/IEC 15948
// §5.3): the 8-byte signature, then chunks of a 4-byte big-endian data length, a 4-byte
// type, the data and a 4-byte CRC, up to IEND.
#include "png_scan.h"

namespace softpbr::image::detail {

std::string png_truncation(std::span<const std::uint8_t> file) {
  const std::uint64_t size = file.size();
  std::uint64_t at = 8;  // after the signature
  for (;;) {
    if (at + 8 > size) return "";  // no IEND: stb reports the missing data
    const std::uint8_t* head = file.data() + at;
    const std::uint64_t length = std::uint64_t{head[0]} << 24 | std::uint64_t{head[1]} << 16 |
                                 std::uint64_t{head[2]} << 8 | std::uint64_t{head[3]};
    const std::string type(reinterpret_cast<const char*>(head + 4), 4);
    at += 8;
    if (at + length + 4 > size) {
      std::string printable;
      for (char c : type) printable += (c >= 32 && c < 127) ? c : '?';
      return "truncated: chunk '" + printable + "' at byte " + std::to_string(at - 8) + " claims " +
             std::to_string(length) + " bytes, more than the file has left";
    }
    if (type == "IEND") return "";
    at += length + 4;
  }
}

}  // namespace softpbr::image::detail
