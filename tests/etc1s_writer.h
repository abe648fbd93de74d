// A minimal BasisLZ (ETC1S) writer for the KTX2 test suites: given the codebooks and each
// block's endpoint and selector, the global data and a level's slices, written in the
// simplest legal forms of the format (KTX 2.0 §3.12.2; Basis Universal's ETC1S texture
// specification). Every Huffman table gives all of its 2^L symbols length L, so a symbol's
// code is the symbol itself in L bits; the table itself is then a one-symbol code-length
// code (length 1, code 0) and a 0 bit per symbol. Endpoints are always coded as deltas
// (prediction symbol 255: four times "delta"), selectors as codebook indices, the selector
// codebook raw. Not an encoder: the tests choose the blocks.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

namespace ktx2_test {

struct Etc1sEndpointSpec {
  int r, g, b, inten;  // 5-bit colour, intensity table 0..7
};

struct Etc1sBlock {
  int endpoint, selector;
};

// Bits appended least significant first, as Basis Universal reads them.
class BitWriter {
 public:
  void put(std::uint32_t value, int count) {
    for (int i = 0; i < count; ++i) bit((value >> i) & 1);
  }
  // A code of `length` bits, most significant bit first (how prefix codes are read).
  void code(std::uint32_t value, int length) {
    for (int i = length - 1; i >= 0; --i) bit((value >> i) & 1);
  }
  // A table of 2^length symbols, each of code length `length` (1..16).
  void table(int length) {
    static constexpr int kOrder[21] = {17, 18, 19, 20, 0, 8, 7, 9, 6, 10, 5, 11, 4, 12, 3, 13, 2, 14, 1, 15, 16};
    const int symbols = 1 << length;
    put(static_cast<std::uint32_t>(symbols), 14);
    int position = 0;
    while (kOrder[position] != length) ++position;
    put(static_cast<std::uint32_t>(position + 1), 5);
    for (int i = 0; i <= position; ++i) put(i == position ? 1 : 0, 3);
    for (int s = 0; s < symbols; ++s) bit(0);  // code-length code 0 = length `length`
  }
  std::vector<std::uint8_t> bytes() const { return bytes_; }

 private:
  void bit(std::uint32_t b) {
    if (count_ % 8 == 0) bytes_.push_back(0);
    bytes_.back() = static_cast<std::uint8_t>(bytes_.back() | (b << (count_ % 8)));
    ++count_;
  }
  std::vector<std::uint8_t> bytes_;
  std::size_t count_ = 0;
};

// Bits of a table holding at least n symbols.
inline int table_bits(int n) {
  int l = 1;
  while ((1 << l) < n) ++l;
  return l;
}

struct Etc1sData {
  std::vector<std::uint8_t> sgd;    // the global data
  std::vector<std::uint8_t> level;  // the level's slices: colour, then alpha
};

// One level of bw × bh blocks (row by row); `alpha` the alpha slice's blocks, or empty.
inline Etc1sData write_etc1s(const std::vector<Etc1sEndpointSpec>& endpoints,
                             const std::vector<std::array<std::uint8_t, 4>>& selectors, int bw, int bh,
                             const std::vector<Etc1sBlock>& colour, const std::vector<Etc1sBlock>& alpha) {
  constexpr int kHistory = 4;
  // One bit more than the codebook needs: room for deltas past it (tests of bad indices).
  const int delta_bits = table_bits(static_cast<int>(endpoints.size())) + 1;
  const int selector_bits = table_bits(static_cast<int>(selectors.size()) + kHistory + 1);
  // Endpoint codebook: three colour-delta tables and the intensity-delta table, grey = 0.
  BitWriter e;
  for (int i = 0; i < 3; ++i) e.table(5);
  e.table(3);
  e.put(0, 1);
  int prev[3] = {16, 16, 16}, prev_inten = 0;
  for (const Etc1sEndpointSpec& p : endpoints) {
    e.code(static_cast<std::uint32_t>((p.inten - prev_inten) & 7), 3);
    prev_inten = p.inten;
    const int v[3] = {p.r, p.g, p.b};
    for (int c = 0; c < 3; ++c) {
      e.code(static_cast<std::uint32_t>((v[c] - prev[c]) & 31), 5);
      prev[c] = v[c];
    }
  }
  // Selector codebook: not global, not hybrid, raw.
  BitWriter s;
  s.put(0, 1);
  s.put(0, 1);
  s.put(1, 1);
  for (const auto& sel : selectors)
    for (std::uint8_t row : sel) s.put(row, 8);
  // Slice tables, then the history buffer's size.
  BitWriter t;
  t.table(9);  // endpoint predictions: 257 symbols used of 512
  t.table(delta_bits);
  t.table(selector_bits);
  t.table(6);
  t.put(kHistory, 13);
  // A slice: a prediction symbol per 2×2 group (255: all four deltas), then per block the
  // endpoint delta and the selector index.
  auto slice = [&](const std::vector<Etc1sBlock>& blocks) {
    BitWriter w;
    int prev_endpoint = 0;
    const int n = static_cast<int>(endpoints.size());
    for (int by = 0; by < bh; ++by)
      for (int bx = 0; bx < bw; ++bx) {
        if ((bx & 1) == 0 && (by & 1) == 0) w.code(255, 9);
        const Etc1sBlock& b = blocks[static_cast<std::size_t>(by * bw + bx)];
        w.code(static_cast<std::uint32_t>(b.endpoint >= prev_endpoint ? b.endpoint - prev_endpoint : b.endpoint - prev_endpoint + n),
               delta_bits);
        prev_endpoint = b.endpoint;
        w.code(static_cast<std::uint32_t>(b.selector), selector_bits);
      }
    return w.bytes();
  };
  Etc1sData out;
  const std::vector<std::uint8_t> eb = e.bytes(), sb = s.bytes(), tb = t.bytes();
  const std::vector<std::uint8_t> rgb = slice(colour);
  const std::vector<std::uint8_t> a = alpha.empty() ? std::vector<std::uint8_t>{} : slice(alpha);
  out.level = rgb;
  out.level.insert(out.level.end(), a.begin(), a.end());
  auto put = [&](std::vector<std::uint8_t>& v, std::uint32_t x, int bytes) {
    for (int i = 0; i < bytes; ++i) v.push_back(static_cast<std::uint8_t>(x >> (8 * i)));
  };
  put(out.sgd, static_cast<std::uint32_t>(endpoints.size()), 2);
  put(out.sgd, static_cast<std::uint32_t>(selectors.size()), 2);
  put(out.sgd, static_cast<std::uint32_t>(eb.size()), 4);
  put(out.sgd, static_cast<std::uint32_t>(sb.size()), 4);
  put(out.sgd, static_cast<std::uint32_t>(tb.size()), 4);
  put(out.sgd, 0, 4);
  // The one image: flags, colour slice, alpha slice.
  put(out.sgd, 0, 4);
  put(out.sgd, 0, 4);
  put(out.sgd, static_cast<std::uint32_t>(rgb.size()), 4);
  put(out.sgd, static_cast<std::uint32_t>(rgb.size()), 4);
  put(out.sgd, static_cast<std::uint32_t>(a.size()), 4);
  out.sgd.insert(out.sgd.end(), eb.begin(), eb.end());
  out.sgd.insert(out.sgd.end(), sb.begin(), sb.end());
  out.sgd.insert(out.sgd.end(), tb.begin(), tb.end());
  return out;
}

}  // namespace ktx2_test
