// The chunk-length check of PNG files (see png_scan.h). Layout (PNG spec, ISO/IEC 15948
// §5.3): the 8-byte signature, then chunks of a 4-byte big-endian data length, a 4-byte
// type, the data and a 4-byte CRC, up to IEND.
#include "png_scan.h"

namespace softpbr::image::detail {

namespace {

std::uint64_t be32(const std::uint8_t* p) {
  return std::uint64_t{p[0]} << 24 | std::uint64_t{p[1]} << 16 | std::uint64_t{p[2]} << 8 | std::uint64_t{p[3]};
}

// Bits a pixel of IHDR's colour type and bit depth holds (ISO/IEC 15948 §11.2.2): 0 for
// a combination PNG does not define (the decoder refuses those itself).
std::uint64_t bits_per_pixel(std::uint8_t color_type, std::uint8_t depth) {
  const std::uint64_t channels = color_type == 0 ? 1 : color_type == 2 ? 3 : color_type == 3 ? 1 : color_type == 4 ? 2
                                 : color_type == 6 ? 4 : 0;
  return channels * depth;
}

// Deflate (RFC 1951) writes at most 258 bytes (one match) for 2 bits (a 1-bit length
// code and a 1-bit distance code): a stream of C bytes inflates to at most 1032·C bytes.
constexpr std::uint64_t kMaxDeflateRatio = 1032;

}  // namespace

std::string png_truncation(std::span<const std::uint8_t> file) {
  const std::uint64_t size = file.size();
  std::uint64_t at = 8;  // after the signature
  std::uint64_t width = 0, height = 0, bits = 0, idat = 0;
  for (;;) {
    if (at + 8 > size) return "";  // no IEND: the decoder reports the missing data
    const std::uint8_t* head = file.data() + at;
    const std::uint64_t length = be32(head);
    const std::string type(reinterpret_cast<const char*>(head + 4), 4);
    at += 8;
    if (at + length + 4 > size) {
      std::string printable;
      for (char c : type) printable += (c >= 32 && c < 127) ? c : '?';
      return "truncated: chunk '" + printable + "' at byte " + std::to_string(at - 8) + " claims " +
             std::to_string(length) + " bytes, more than the file has left";
    }
    if (type == "IHDR" && length >= 13) {
      width = be32(file.data() + at);
      height = be32(file.data() + at + 4);
      bits = bits_per_pixel(file[at + 9], file[at + 8]);
    }
    if (type == "IDAT") idat += length;
    if (type == "IEND") break;
    at += length + 4;
  }
  // The image's filtered scanlines are at least its pixels' bytes (⌊w·h·bits / 8⌋, interlaced
  // or not): compressed data that cannot inflate to them is refused before the decoder
  // allocates the image (a 1.4 kB file declaring 16384² RGBA reached 1 GiB and 1.9 s first).
  // (Sides up to 2^24, bits up to 64: the product stays below 2^51. Larger sides are over
  // every decoder's limit, refused from IHDR before this walk.)
  constexpr std::uint64_t kSide = std::uint64_t{1} << 24;
  if (width == 0 || height == 0 || bits == 0 || width > kSide || height > kSide) return "";
  const std::uint64_t pixels = width * bits / 8 * height;
  if (pixels / kMaxDeflateRatio > idat + 1)
    return "truncated: its " + std::to_string(idat) + " bytes of compressed image data (IDAT) cannot hold the " +
           std::to_string(width) + "x" + std::to_string(height) + " image it declares (" + std::to_string(pixels) +
           " bytes; deflate expands at most " + std::to_string(kMaxDeflateRatio) + "-fold)";
  return "";
}

}  // namespace softpbr::image::detail
