// The chunk-length check of PNG files (see png_scan.h). Layout (PNG spec, ISO/IEC 15948
// §5.3): the 8-byte signature, then chunks of a 4-byte big-endian data length, a 4-byte
// type, the data and a 4-byte CRC, up to IEND.
#include "png_scan.h"

#include <cstdint>

namespace softpbr::golden::detail {

std::string png_truncation(std::FILE* file) {
  if (std::fseek(file, 0, SEEK_END) != 0) return "cannot measure the file";
  const long size = std::ftell(file);
  if (size < 0 || std::fseek(file, 8, SEEK_SET) != 0) return "cannot measure the file";
  std::uint64_t at = 8;  // after the signature
  for (;;) {
    unsigned char head[8];
    if (std::fread(head, 1, 8, file) != 8) return "";  // no IEND: stb reports the missing data
    const std::uint64_t length = std::uint64_t{head[0]} << 24 | std::uint64_t{head[1]} << 16 |
                                 std::uint64_t{head[2]} << 8 | std::uint64_t{head[3]};
    const std::string type(reinterpret_cast<const char*>(head + 4), 4);
    at += 8;
    if (at + length + 4 > static_cast<std::uint64_t>(size)) {
      std::string printable;
      for (char c : type) printable += (c >= 32 && c < 127) ? c : '?';
      return "truncated: chunk '" + printable + "' at byte " + std::to_string(at - 8) + " claims " +
             std::to_string(length) + " bytes, more than the file has left";
    }
    if (type == "IEND") return "";
    at += length + 4;
    if (std::fseek(file, static_cast<long>(at), SEEK_SET) != 0) return "cannot seek in the file";
  }
}

}  // namespace softpbr::golden::detail
