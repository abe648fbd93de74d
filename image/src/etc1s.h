// Internal to softpbr_image: ETC1S images in BasisLZ supercompression (KTX 2.0 §3.12.2,
// "BasisLZ Global Data"; the Basis Universal ETC1S texture specification) decoded to RGBA8.
//
// The global data holds the codebooks every level shares: endpoints (a 5-bit RGB colour and
// a 3-bit ETC1 intensity table index, delta-coded with Huffman models) and selectors (a 2-bit
// index per texel of a 4×4 block, XOR-delta coded), then the Huffman tables of the slices.
// A slice codes each block's endpoint (predicted from its left, upper or upper-left
// neighbour, or a delta from the previous one) and selector (a codebook index, or an entry of
// a move-to-front history buffer, with runs). A block's texels are ETC1's "differential"
// mode with one colour for both halves (KHR Data Format Specification 1.3, §21.1): the
// colour widened to 8 bits, plus the table's modifier for the selector, clamped to 0..255.
// An alpha slice is decoded the same way and gives alpha from its green channel. The
// Huffman decoding of a slice is sequential; expanding its blocks to texels is not.
//
// Every Huffman table is validated (a complete prefix code, or a single symbol) and every
// codebook index and history-buffer reference checked; a slice that reads past its end is
// an error. Integer arithmetic throughout.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace softpbr::image::detail {

// A canonical prefix code as Basis Universal writes them: code lengths 1–16, codes
// assigned in order of length then symbol, read from the stream's least significant bit
// first, most significant code bit first.
class Etc1sHuffman {
 public:
  bool empty() const { return symbols_.empty(); }
  // From code lengths (0: unused); false unless they form a complete code or use one symbol.
  bool init(std::span<const std::uint8_t> lengths);
  template <class Bits>
  int decode(Bits& bits) const;  // -1: no symbol (an incomplete single-symbol code)

 private:
  std::array<std::uint16_t, 17> count_{};  // codes of each length
  std::vector<std::uint16_t> symbols_;     // by length, then symbol
};

struct Etc1sEndpoint {
  std::uint8_t r = 0, g = 0, b = 0;  // 5-bit
  std::uint8_t inten = 0;            // 0..7
};

struct Etc1sImageDesc {
  std::uint32_t flags = 0;
  std::uint32_t rgb_offset = 0, rgb_length = 0, alpha_offset = 0, alpha_length = 0;
};

// The global data's codebooks and slice tables, read once for all levels.
struct Etc1sGlobal {
  std::vector<Etc1sEndpoint> endpoints;
  std::vector<std::array<std::uint8_t, 4>> selectors;  // a byte a row, texel x at bits 2x
  Etc1sHuffman endpoint_pred, delta_endpoint, selector, history_rle;
  int history_size = 0;
  std::vector<Etc1sImageDesc> images;  // one per level (2D textures: one layer, one face)
};

// Reads the global data of a texture of `levels` images. Returns "" or what is wrong.
std::string etc1s_read_global(std::span<const std::uint8_t> sgd, int levels, Etc1sGlobal& out);

// A block's codebook entries, as a slice codes them.
struct Etc1sBlock {
  std::uint16_t endpoint = 0, selector = 0;
};

// Decodes a slice of a w×h image — its Huffman codes, one after the other — into `blocks`,
// one per 4×4 block, rows of (w + 3) / 4 top down ((w + 3) / 4 · (h + 3) / 4 of them), every
// endpoint and selector checked against the codebooks. Returns "" or what is wrong.
std::string etc1s_decode_slice(const Etc1sGlobal& g, std::span<const std::uint8_t> slice, int w, int h,
                               std::span<Etc1sBlock> blocks);

// Expands block rows [by_begin, by_end) of a slice's `blocks` (etc1s_decode_slice's) into
// the w×h `rgba` (w·h·4 bytes): the colour channels and alpha 255 or, with `alpha`, the
// alpha channel only. Block rows are independent: ranges may run on different threads at once.
void etc1s_expand(const Etc1sGlobal& g, std::span<const Etc1sBlock> blocks, int w, int h, int by_begin, int by_end,
                  std::uint8_t* rgba, bool alpha);

}  // namespace softpbr::image::detail
