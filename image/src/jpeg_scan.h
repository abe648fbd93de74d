// Internal to softpbr_image: a walk over a JPEG file's markers, run before stb_image
// decodes it, that reads the frame header (SOF) and refuses files whose structure is cut
// short or is not JPEG's.
//
// Why: stb_image (v2.27 in Debian 12's libstb-dev) reads zeros past the end of the data
// and decodes on, so a few hundred bytes whose frame header claims 16384 × 16384 pixels
// would make it allocate and decode a whole image from nothing, as its TGA and .hdr
// decoders did before hdr_scan.h and the signature checks (fuzz/README.md, Findings).
// The walk requires every segment to fit in the file, one supported frame header, Huffman
// tables stb can build (stb_image 2.27 writes past its arrays for a table of more than 256
// codes, found by fuzz_image), at least one scan, and the end-of-image marker; and for sequential (baseline or extended) files,
// coded data of at least 2 bits a block — the shortest a block can be coded in (a 1-bit
// DC code for "no difference" and a 1-bit end-of-block code), so the decode's work is
// bounded by the file's size. Progressive files code runs of empty blocks in a few bits
// (EOBRUN) and get only the size limits.
#pragma once

#include <cstdint>
#include <span>
#include <string>

namespace softpbr::image::detail {

struct JpegScan {
  int width = 0;   // from the frame header; 0 when none was read
  int height = 0;
  int components = 0;
  bool progressive = false;
  // Samples of the component planes stb_image allocates (each padded to whole MCUs): it
  // decodes into them at 1 byte a sample and, for progressive files, also keeps 2 bytes of
  // coefficients a sample.
  std::uint64_t plane_samples = 0;
  std::string problem;  // "" when the structure is sound, else what is wrong
};

// Walks `file` (a whole file starting with the SOI marker) up to its EOI marker.
JpegScan jpeg_scan(std::span<const std::uint8_t> file);

}  // namespace softpbr::image::detail
