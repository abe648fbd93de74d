// The marker walk of JPEG files (see jpeg_scan.h). Layout (ITU-T T.81, Annex B): SOI
// (FF D8), then marker segments — FF, a marker code, a 2-byte big-endian length that counts
// itself, the payload — with any number of FF fill bytes before a marker code; RSTn
// (FF D0..D7), TEM (FF 01) and EOI (FF D9) have no length. After a scan header (SOS, FF DA)
// comes entropy-coded data, in which FF is followed by 00 (a stuffed FF byte) or a RSTn
// marker, up to the next marker. The frame header (SOFn, B.2.2): precision, height and
// width (2 bytes each), the component count, and 3 bytes per component (id, sampling
// factors H:V in the two nibbles, quantisation table).
#include "jpeg_scan.h"

#include <algorithm>
#include <cstdio>
#include <utility>

namespace softpbr::image::detail {

namespace {

std::string hex(int marker) {
  char text[8];
  std::snprintf(text, sizeof text, "FF%02X", marker & 0xff);
  return text;
}

bool is_sof(int m) { return m >= 0xc0 && m <= 0xcf && m != 0xc4 && m != 0xc8 && m != 0xcc; }

// Reads the frame header's payload `p` (length bytes after the length field) into `out`;
// returns what is wrong with it, or "".
std::string read_frame_header(int marker, const std::uint8_t* p, std::size_t length, JpegScan& out) {
  // stb_image decodes baseline (SOF0), extended sequential Huffman (SOF1) and progressive
  // Huffman (SOF2); lossless, hierarchical and arithmetic-coded files it does not.
  if (marker != 0xc0 && marker != 0xc1 && marker != 0xc2)
    return "frame header " + hex(marker) + ": lossless, hierarchical and arithmetic-coded JPEG are not supported";
  if (length < 6) return "frame header " + hex(marker) + " is too short";
  const int precision = p[0];
  const int height = p[1] << 8 | p[2], width = p[3] << 8 | p[4], n = p[5];
  if (length != 6 + 3 * static_cast<std::size_t>(n))
    return "frame header " + hex(marker) + ": its length does not match its " + std::to_string(n) + " components";
  if (precision != 8) return "frame header: " + std::to_string(precision) + "-bit samples are not supported (8-bit only)";
  if (n != 1 && n != 3 && n != 4) return "frame header: " + std::to_string(n) + " components (expected 1, 3 or 4)";
  for (int c = 0; c < n; ++c) {
    const int h = p[7 + 3 * c] >> 4, v = p[7 + 3 * c] & 15, table = p[8 + 3 * c];
    if (h < 1 || h > 4 || v < 1 || v > 4 || table > 3)
      return "frame header: component " + std::to_string(c) + " has sampling " + std::to_string(h) + "x" +
             std::to_string(v) + " and table " + std::to_string(table) + " (expected 1..4, 1..4 and 0..3)";
  }
  // Height 0 (given later by a DNL marker) stb_image does not support.
  if (width == 0 || height == 0)
    return "frame header: size " + std::to_string(width) + "x" + std::to_string(height) + " (a side of 0 is not supported)";
  out.width = width;
  out.height = height;
  out.components = n;
  out.progressive = marker == 0xc2;
  int hmax = 1, vmax = 1;
  for (int c = 0; c < n; ++c) {
    hmax = std::max(hmax, p[7 + 3 * c] >> 4);
    vmax = std::max(vmax, p[7 + 3 * c] & 15);
  }
  const std::uint64_t mcus_x = (width + 8 * hmax - 1) / (8 * hmax), mcus_y = (height + 8 * vmax - 1) / (8 * vmax);
  for (int c = 0; c < n; ++c)
    out.plane_samples += mcus_x * (p[7 + 3 * c] >> 4) * 8 * (mcus_y * (p[7 + 3 * c] & 15) * 8);
  return "";
}

// Checks a DHT segment's payload (T.81 B.2.4.2): tables of a class/id byte, 16 counts of
// codes per length and the code values. stb_image 2.27 copies the counts' sum of lengths
// and values into arrays of 257 and 256 entries without checking it (fuzz_image found the
// overflow: up to 16 × 255 codes), so a table may have at most 256 codes, and the code
// lengths must fit (at most 2^L codes of length L, after the shorter ones).
std::string check_huffman_tables(const std::uint8_t* p, std::size_t length) {
  while (length > 0) {
    if (length < 17) return "Huffman table segment (FFC4) ends inside a table header";
    const int table_class = p[0] >> 4, id = p[0] & 15;
    if (table_class > 1 || id > 3)
      return "Huffman table class " + std::to_string(table_class) + ", id " + std::to_string(id) +
             " (expected 0..1, 0..3)";
    std::size_t codes = 0;
    for (int bits = 1; bits <= 16; ++bits) codes += p[bits];
    if (codes > 256) return "Huffman table of " + std::to_string(codes) + " codes (at most 256)";
    std::uint32_t end = 0;  // one past the last code of the current length (T.81 C.2)
    for (int bits = 1; bits <= 16; ++bits) {
      end += p[bits];
      if (end > (std::uint32_t{1} << bits))
        return "Huffman table: more codes of length " + std::to_string(bits) + " than fit";
      end <<= 1;
    }
    if (length < 17 + codes) return "Huffman table segment (FFC4) ends inside a table's values";
    p += 17 + codes;
    length -= 17 + codes;
  }
  return "";
}

// The fewest 8×8 blocks a sequential file of this frame codes: each component's own blocks
// (a scan of several components pads to whole MCUs, which only adds blocks).
std::uint64_t fewest_blocks(const std::uint8_t* frame, int width, int height) {
  const int n = frame[5];
  int hmax = 1, vmax = 1;
  for (int c = 0; c < n; ++c) {
    hmax = std::max(hmax, frame[7 + 3 * c] >> 4);
    vmax = std::max(vmax, frame[7 + 3 * c] & 15);
  }
  std::uint64_t blocks = 0;
  for (int c = 0; c < n; ++c) {
    const std::uint64_t h = frame[7 + 3 * c] >> 4, v = frame[7 + 3 * c] & 15;
    const std::uint64_t cw = (static_cast<std::uint64_t>(width) * h + hmax - 1) / hmax;
    const std::uint64_t ch = (static_cast<std::uint64_t>(height) * v + vmax - 1) / vmax;
    blocks += (cw + 7) / 8 * ((ch + 7) / 8);
  }
  return blocks;
}

}  // namespace

JpegScan jpeg_scan(std::span<const std::uint8_t> file) {
  JpegScan out;
  const auto refuse = [&](std::string why) {
    out.problem = std::move(why);
    return out;
  };
  const std::size_t size = file.size();
  const std::uint8_t* frame = nullptr;  // the frame header's payload
  std::uint64_t coded_bytes = 0;        // entropy-coded data, all scans
  int scans = 0;
  std::size_t at = 2;  // after SOI
  for (;;) {
    if (at >= size) return refuse("truncated: the file ends before its end-of-image marker");
    if (file[at] != 0xff)
      return refuse("not JPEG data: byte " + std::to_string(at) + " is not a marker");
    while (at < size && file[at] == 0xff) ++at;  // fill bytes
    if (at >= size) return refuse("truncated: the file ends before its end-of-image marker");
    const int marker = file[at++];
    const std::size_t marker_at = at - 2;
    if (marker == 0xd9) break;  // EOI
    if (marker == 0x01 || (marker >= 0xd0 && marker <= 0xd7)) continue;  // TEM, RSTn: no length
    if (marker == 0x00 || marker == 0xd8)
      return refuse("not JPEG data: marker " + hex(marker) + " at byte " + std::to_string(marker_at));
    if (at + 2 > size) return refuse("truncated: the file ends inside marker " + hex(marker));
    const std::size_t length = static_cast<std::size_t>(file[at]) << 8 | file[at + 1];
    if (length < 2) return refuse("not JPEG data: marker " + hex(marker) + " has length " + std::to_string(length));
    if (at + length > size)
      return refuse("truncated: segment " + hex(marker) + " at byte " + std::to_string(marker_at) + " claims " +
                           std::to_string(length) + " bytes, more than the file has left");
    const std::uint8_t* payload = file.data() + at + 2;
    at += length;
    if (is_sof(marker)) {
      if (frame) return refuse("not JPEG data: a second frame header at byte " + std::to_string(marker_at));
      if (std::string p = read_frame_header(marker, payload, length - 2, out); !p.empty()) return refuse(std::move(p));
      frame = payload;
    } else if (marker == 0xc4) {
      if (std::string p = check_huffman_tables(payload, length - 2); !p.empty()) return refuse(std::move(p));
    } else if (marker == 0xda) {  // SOS, then entropy-coded data up to the next marker
      if (!frame) return refuse("not JPEG data: a scan before the frame header");
      ++scans;
      const std::size_t start = at;
      for (;;) {
        while (at < size && file[at] != 0xff) ++at;
        std::size_t next = at;
        while (next < size && file[next] == 0xff) ++next;
        if (next >= size) return refuse("truncated: the file ends inside coded data");
        const int code = file[next];
        if (code == 0x00 || (code >= 0xd0 && code <= 0xd7)) {  // a stuffed FF or a restart marker
          at = next + 1;
          continue;
        }
        break;  // a marker: `at` is its first FF
      }
      coded_bytes += at - start;
    }
  }
  if (!frame) return refuse("not JPEG data: no frame header before the end-of-image marker");
  if (scans == 0) return refuse("not JPEG data: no scan before the end-of-image marker");
  if (!out.progressive) {
    const std::uint64_t blocks = fewest_blocks(frame, out.width, out.height);
    if (coded_bytes * 8 < blocks * 2)
      return refuse("truncated: " + std::to_string(coded_bytes) + " bytes of coded data cannot hold the " +
                           std::to_string(blocks) + " blocks of a " + std::to_string(out.width) + "x" +
                           std::to_string(out.height) + " image");
  }
  return out;
}

}  // namespace softpbr::image::detail
