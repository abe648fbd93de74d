// The truncation check of Radiance .hdr pixel data (see hdr_scan.h). It follows
// stbi__hdr_load in stb_image.h: header lines up to an empty line, the resolution line,
// then either flat RGBE pixels (width < 8 or ≥ 32768) or, per scanline, the new-style RLE
// marker (2, 2, width high byte with bit 7 clear, width low byte) and four component runs;
// a scanline without the marker switches stb to flat pixels for the rest of the image.
#include "hdr_scan.h"

namespace softpbr::image::detail {

namespace {

// Byte reader over the file that counts what it has read.
class Reader {
 public:
  explicit Reader(std::span<const std::uint8_t> bytes) : bytes_(bytes) {}
  // The next byte, or −1 at the end.
  int next() { return read_ < bytes_.size() ? bytes_[read_++] : -1; }
  // Skips `n` bytes; false if the file ends first (having read all of it).
  bool skip(std::uint64_t n) {
    const std::uint64_t left = bytes_.size() - read_;
    read_ += n < left ? n : left;
    return n <= left;
  }
  std::uint64_t read() const { return read_; }

 private:
  std::span<const std::uint8_t> bytes_;
  std::uint64_t read_ = 0;
};

std::string missing(const char* what, std::uint64_t at) {
  return std::string("truncated: the pixel data ends inside ") + what + " (after " + std::to_string(at) +
         " bytes of the file)";
}

}  // namespace

std::string hdr_truncation(std::span<const std::uint8_t> file, int width, int height) {
  Reader in(file);
  // Header: the magic line, lines up to an empty one, then the resolution line. stb reads
  // each line into a C string, so a line that starts with a NUL byte is empty to it too
  // (fuzz_image found a header that ends there for stb, which then decoded 16384 x 1638
  // pixels from past the end, while this walk saw no empty line).
  int empty_lines_seen = 0, line_length = 0, lines = 0;
  bool starts_with_nul = false;
  for (;;) {
    const int c = in.next();
    // The file ends in the header (stb reports a bad header itself), or on the resolution
    // line: stb parses that line and then reads every pixel from past the end.
    if (c < 0) return empty_lines_seen == 1 ? missing("the resolution line: there is no pixel data", in.read()) : "";
    if (c != '\n') {
      if (line_length++ == 0) starts_with_nul = c == 0;
      continue;
    }
    ++lines;
    if (lines > 1 && (line_length == 0 || starts_with_nul) && empty_lines_seen == 0) empty_lines_seen = 1;
    else if (empty_lines_seen == 1) break;  // the resolution line just ended
    line_length = 0;
    starts_with_nul = false;
  }

  const std::uint64_t pixels = static_cast<std::uint64_t>(width) * static_cast<std::uint64_t>(height);
  if (width < 8 || width >= 32768)
    return in.skip(pixels * 4) ? "" : missing("the flat pixels", in.read());
  for (int y = 0; y < height; ++y) {
    const int c1 = in.next(), c2 = in.next(), hi = in.next();
    if (hi < 0) return missing("a scanline marker", in.read());
    if (c1 != 2 || c2 != 2 || (hi & 0x80) != 0)  // not RLE: stb decodes the rest flat, from pixel 1
      return in.skip(4 + (pixels - 1) * 4 - 3) ? "" : missing("the flat pixels", in.read());
    const int lo = in.next();
    if (lo < 0) return missing("a scanline marker", in.read());
    if ((hi << 8 | lo) != width) return "";  // stb: "invalid decoded scanline length"
    for (int k = 0; k < 4; ++k)
      for (int i = 0; i < width;) {
        int count = in.next();
        if (count < 0) return missing("a run-length encoded scanline", in.read());
        if (count > 128) {
          count -= 128;
          if (in.next() < 0) return missing("a run-length encoded scanline", in.read());
        } else if (count <= width - i && !in.skip(static_cast<std::uint64_t>(count))) {
          return missing("a run-length encoded scanline", in.read());
        }
        if (count > width - i) return "";  // stb: "bad RLE data in HDR"
        i += count;
      }
  }
  return "";
}

}  // namespace softpbr::image::detail
