// ETC1S / BasisLZ decoding (see etc1s.h). Section names are the Basis Universal ETC1S
// texture specification's and KTX 2.0's §3.12.2.
#include "etc1s.h"

#include <algorithm>

namespace softpbr::image::detail {

namespace {

// The slice's bits, least significant bit of each byte first. Reads past the end give
// zeros and are remembered: a slice that needs them is truncated.
class Bits {
 public:
  explicit Bits(std::span<const std::uint8_t> data) : data_(data) {}
  std::uint32_t get(int count) {  // count ≤ 32
    std::uint32_t v = 0;
    for (int i = 0; i < count; ++i, ++pos_)
      if (pos_ < data_.size() * 8) v |= std::uint32_t((data_[pos_ >> 3] >> (pos_ & 7)) & 1) << i;
    return v;
  }
  bool overrun() const { return pos_ > data_.size() * 8; }

  // "VLC": chunks of chunk_bits value bits, each followed by a bit saying another follows.
  std::uint32_t vlc(int chunk_bits) {
    std::uint32_t v = 0;
    for (int shift = 0; shift < 32; shift += chunk_bits) {
      const std::uint32_t s = get(chunk_bits + 1);
      v |= (s & ((1u << chunk_bits) - 1)) << shift;
      if ((s >> chunk_bits) == 0) break;
    }
    return v;
  }

 private:
  std::span<const std::uint8_t> data_;
  std::size_t pos_ = 0;
};

// "Huffman table format": the number of symbols (14 bits); the code lengths of the 21
// code-length codes (5 bits of count, 3 bits each, in the order below); then the symbols'
// lengths in that code: 0–16 literally, 17/18 a run of zeros (3 + 3 bits, 11 + 7 bits), 19/20
// a run of the previous length (3 + 2 bits, 7 + 7 bits).
constexpr int kMaxSymbols = 1 << 14;
constexpr std::array<std::uint8_t, 21> kCodeLengthOrder = {17, 18, 19, 20, 0, 8,  7, 9,  6, 10, 5,
                                                           11, 4,  12, 3,  13, 2, 14, 1, 15, 16};

bool read_table(Bits& bits, Etc1sHuffman& table) {
  table = {};
  const int symbols = static_cast<int>(bits.get(14));
  if (symbols == 0) return true;  // an empty table: valid where nothing is coded with it
  const int lengths_coded = static_cast<int>(bits.get(5));
  if (lengths_coded < 1 || lengths_coded > 21) return false;
  std::array<std::uint8_t, 21> cl_lengths{};
  for (int i = 0; i < lengths_coded; ++i) cl_lengths[kCodeLengthOrder[static_cast<std::size_t>(i)]] = static_cast<std::uint8_t>(bits.get(3));
  Etc1sHuffman cl;
  if (!cl.init(cl_lengths) || cl.empty()) return false;
  std::vector<std::uint8_t> lengths(static_cast<std::size_t>(symbols), 0);
  int at = 0;
  while (at < symbols) {
    const int c = cl.decode(bits);
    if (c < 0 || bits.overrun()) return false;
    if (c <= 16) {
      lengths[static_cast<std::size_t>(at++)] = static_cast<std::uint8_t>(c);
    } else if (c == 17 || c == 18) {
      at += c == 17 ? static_cast<int>(bits.get(3)) + 3 : static_cast<int>(bits.get(7)) + 11;
    } else {
      if (at == 0 || lengths[static_cast<std::size_t>(at - 1)] == 0) return false;
      const int run = c == 19 ? static_cast<int>(bits.get(2)) + 3 : static_cast<int>(bits.get(7)) + 7;
      if (at + run > symbols) return false;
      std::fill_n(lengths.begin() + at, run, lengths[static_cast<std::size_t>(at - 1)]);
      at += run;
    }
  }
  if (at != symbols) return false;  // a zero run past the last symbol
  return table.init(lengths) && !table.empty();
}

// ETC1's intensity modifier tables (KHR Data Format Specification 1.3, §21.1, Table 128),
// in the order of Basis Universal's selectors: 0 the most negative.
constexpr std::array<std::array<int, 4>, 8> kModifiers = {{
    {-8, -2, 2, 8},
    {-17, -5, 5, 17},
    {-29, -9, 9, 29},
    {-42, -13, 13, 42},
    {-60, -18, 18, 60},
    {-80, -24, 24, 80},
    {-106, -33, 33, 106},
    {-183, -47, 47, 183},
}};

}  // namespace

bool Etc1sHuffman::init(std::span<const std::uint8_t> lengths) {
  count_ = {};
  symbols_.clear();
  int used = 0;
  for (const std::uint8_t l : lengths) {
    if (l > 16) return false;
    if (l) {
      ++count_[l];
      ++used;
    }
  }
  if (used == 0) return false;
  // Kraft's sum over 2^16: a complete code fills it exactly. Basis Universal also accepts
  // one symbol alone (any length), decoded by its all-zero code.
  std::uint64_t kraft = 0;
  for (int l = 1; l <= 16; ++l) kraft += std::uint64_t{count_[static_cast<std::size_t>(l)]} << (16 - l);
  if (kraft != (std::uint64_t{1} << 16) && used != 1) return false;
  for (int l = 1; l <= 16; ++l)
    for (std::size_t s = 0; s < lengths.size(); ++s)
      if (lengths[s] == l) symbols_.push_back(static_cast<std::uint16_t>(s));
  return true;
}

template <class B>
int Etc1sHuffman::decode(B& bits) const {
  // Canonical decoding: the first code of each length follows the last of the shorter ones.
  int code = 0, first = 0, index = 0;
  for (int l = 1; l <= 16; ++l) {
    code |= static_cast<int>(bits.get(1));
    const int n = count_[static_cast<std::size_t>(l)];
    if (code - first < n) return symbols_[static_cast<std::size_t>(index + code - first)];
    index += n;
    first = (first + n) << 1;
    code <<= 1;
  }
  return -1;
}

std::string etc1s_read_global(std::span<const std::uint8_t> sgd, int levels, Etc1sGlobal& g) {
  auto u16 = [&](std::size_t at) { return static_cast<std::uint32_t>(sgd[at] | (sgd[at + 1] << 8)); };
  auto u32 = [&](std::size_t at) { return u16(at) | (u16(at + 2) << 16); };
  // §3.12.2: endpointCount, selectorCount (16 bits), the byte lengths of the endpoints,
  // selectors, tables and extended data (32 bits), then 20 bytes an image, then the data.
  constexpr std::size_t kHeader = 20, kImageDesc = 20;
  const std::uint64_t descs_end = kHeader + kImageDesc * static_cast<std::uint64_t>(levels);
  if (sgd.size() < descs_end)
    return "its BasisLZ global data (" + std::to_string(sgd.size()) + " bytes) is shorter than its header and image descriptions (" +
           std::to_string(descs_end) + ")";
  const std::uint32_t endpoint_count = u16(0), selector_count = u16(2);
  const std::uint64_t endpoints_bytes = u32(4), selectors_bytes = u32(8), tables_bytes = u32(12), extended_bytes = u32(16);
  if (descs_end + endpoints_bytes + selectors_bytes + tables_bytes + extended_bytes != sgd.size())
    return "its BasisLZ global data's lengths do not add up to its " + std::to_string(sgd.size()) + " bytes";
  if (endpoint_count == 0 || selector_count == 0) return "its BasisLZ codebooks are empty";
  for (int i = 0; i < levels; ++i) {
    const std::size_t at = kHeader + kImageDesc * static_cast<std::size_t>(i);
    g.images.push_back({u32(at), u32(at + 4), u32(at + 8), u32(at + 12), u32(at + 16)});
  }
  std::size_t at = descs_end;
  const auto endpoints_data = sgd.subspan(at, endpoints_bytes);
  const auto selectors_data = sgd.subspan(at += endpoints_bytes, selectors_bytes);
  const auto tables_data = sgd.subspan(at += selectors_bytes, tables_bytes);

  // "Endpoint codebook": four tables (colour deltas after a previous value of 0–9, 10–21,
  // 22–31; intensity deltas), a greyscale flag, then each endpoint's deltas.
  {
    Bits bits(endpoints_data);
    Etc1sHuffman colour[3], inten;
    for (Etc1sHuffman& t : colour)
      if (!read_table(bits, t) || t.empty()) return "its BasisLZ endpoint codebook has an invalid Huffman table";
    if (!read_table(bits, inten) || inten.empty()) return "its BasisLZ endpoint codebook has an invalid Huffman table";
    const bool grey = bits.get(1) != 0;
    int prev[3] = {16, 16, 16}, prev_inten = 0;
    g.endpoints.resize(endpoint_count);
    for (Etc1sEndpoint& e : g.endpoints) {
      const int di = inten.decode(bits);
      if (di < 0) return "its BasisLZ endpoint codebook is corrupt";
      e.inten = static_cast<std::uint8_t>((di + prev_inten) & 7);
      prev_inten = e.inten;
      for (int c = 0; c < (grey ? 1 : 3); ++c) {
        const Etc1sHuffman& t = prev[c] <= 9 ? colour[0] : prev[c] <= 21 ? colour[1] : colour[2];
        const int d = t.decode(bits);
        if (d < 0) return "its BasisLZ endpoint codebook is corrupt";
        prev[c] = (prev[c] + d) & 31;
      }
      e.r = static_cast<std::uint8_t>(prev[0]);
      e.g = static_cast<std::uint8_t>(grey ? prev[0] : prev[1]);
      e.b = static_cast<std::uint8_t>(grey ? prev[0] : prev[2]);
    }
    if (bits.overrun()) return "its BasisLZ endpoint codebook is truncated";
  }
  // "Selector codebook": flags (global codebook, hybrid: not in KTX2), raw bytes, or the
  // first entry raw and each later byte XORed with the one before through a Huffman table.
  {
    Bits bits(selectors_data);
    if (bits.get(1) != 0 || bits.get(1) != 0) return "its BasisLZ selector codebook uses a global codebook (not in KTX2)";
    const bool raw = bits.get(1) != 0;
    Etc1sHuffman delta;
    if (!raw && (!read_table(bits, delta) || (selector_count > 1 && delta.empty())))
      return "its BasisLZ selector codebook has an invalid Huffman table";
    g.selectors.resize(selector_count);
    std::array<std::uint8_t, 4> prev{};
    for (std::size_t i = 0; i < g.selectors.size(); ++i)
      for (int row = 0; row < 4; ++row) {
        int byte = 0;
        if (raw || i == 0) {
          byte = static_cast<int>(bits.get(8));
        } else {
          const int d = delta.decode(bits);
          if (d < 0 || d > 255) return "its BasisLZ selector codebook is corrupt";
          byte = d ^ prev[static_cast<std::size_t>(row)];
        }
        prev[static_cast<std::size_t>(row)] = static_cast<std::uint8_t>(byte);
        g.selectors[i][static_cast<std::size_t>(row)] = static_cast<std::uint8_t>(byte);
      }
    if (bits.overrun()) return "its BasisLZ selector codebook is truncated";
  }
  // "Slice tables": endpoint predictions, endpoint deltas, selectors, history-buffer runs,
  // then the history buffer's size (13 bits).
  {
    Bits bits(tables_data);
    for (Etc1sHuffman* t : {&g.endpoint_pred, &g.delta_endpoint, &g.selector, &g.history_rle})
      if (!read_table(bits, *t) || t->empty()) return "its BasisLZ slice tables have an invalid Huffman table";
    g.history_size = static_cast<int>(bits.get(13));
    if (g.history_size == 0) return "its BasisLZ selector history buffer has size 0";
    if (bits.overrun()) return "its BasisLZ slice tables are truncated";
  }
  return "";
}

std::string etc1s_decode_slice(const Etc1sGlobal& g, std::span<const std::uint8_t> slice, int w, int h,
                               std::span<Etc1sBlock> blocks) {
  const int bw = (w + 3) / 4, bh = (h + 3) / 4;
  const std::uint64_t total_blocks = std::uint64_t(bw) * std::uint64_t(bh);
  if (blocks.size() != total_blocks) return "a slice's block buffer does not fit the image";  // the caller's error
  const int selectors = static_cast<int>(g.selectors.size());
  const int endpoints = static_cast<int>(g.endpoints.size());
  Bits bits(slice);

  // "Selector history buffer": an approximate move-to-front list. A new selector is written
  // at the rover, which runs over the second half; a used entry swaps with the one at half
  // its index.
  std::vector<int> history(static_cast<std::size_t>(g.history_size), 0);
  std::size_t rover = history.size() / 2;
  std::uint64_t rle_left = 0;

  // "Endpoint prediction": per 2×2 group of blocks, a symbol of four 2-bit predictions
  // (0 left, 1 above, 2 above-left, 3 a coded delta), 256 repeating the last symbol.
  // Per column: the lower row's predictions and the endpoint of each row (two rows kept).
  struct Column {
    int pred_bits = 0, endpoint = 0;
  };
  std::vector<Column> rows[2] = {std::vector<Column>(static_cast<std::size_t>(bw)), std::vector<Column>(static_cast<std::size_t>(bw))};
  int pred_bits = 0, prev_pred_symbol = 0, pred_repeat = 0, prev_endpoint = 0;

  for (int by = 0; by < bh; ++by) {
    std::vector<Column>& cur = rows[by & 1];
    std::vector<Column>& above = rows[(by & 1) ^ 1];
    for (int bx = 0; bx < bw; ++bx) {
      if ((bx & 1) == 0) {
        if ((by & 1) == 0) {
          if (pred_repeat > 0) {
            --pred_repeat;
            pred_bits = prev_pred_symbol;
          } else {
            pred_bits = g.endpoint_pred.decode(bits);
            if (pred_bits < 0) return "a slice has an invalid endpoint prediction code";
            if (pred_bits == 256) {
              pred_repeat = static_cast<int>(std::min<std::uint32_t>(bits.vlc(4) + 2, 1u << 30));
              pred_bits = prev_pred_symbol;
            } else {
              prev_pred_symbol = pred_bits;
            }
          }
          above[static_cast<std::size_t>(bx)].pred_bits = pred_bits >> 4;  // for the row below
        } else {
          pred_bits = cur[static_cast<std::size_t>(bx)].pred_bits;
        }
      }
      const int pred = pred_bits & 3;
      pred_bits >>= 2;
      int endpoint = 0;
      switch (pred) {
        case 0:
          if (bx == 0) return "a slice predicts a block's endpoint from the left of the image";
          endpoint = prev_endpoint;
          break;
        case 1:
          if (by == 0) return "a slice predicts a block's endpoint from above the image";
          endpoint = above[static_cast<std::size_t>(bx)].endpoint;
          break;
        case 2:
          if (bx == 0 || by == 0) return "a slice predicts a block's endpoint from outside the image";
          endpoint = above[static_cast<std::size_t>(bx - 1)].endpoint;
          break;
        default: {
          const int delta = g.delta_endpoint.decode(bits);
          if (delta < 0) return "a slice has an invalid endpoint delta code";
          endpoint = delta + prev_endpoint;
          if (endpoint >= endpoints) endpoint -= endpoints;
        }
      }
      cur[static_cast<std::size_t>(bx)].endpoint = endpoint;
      prev_endpoint = endpoint;

      // "Selector coding": a codebook index, a history-buffer entry, or a run of history
      // entry 0.
      int symbol = 0;
      if (rle_left > 0) {
        --rle_left;
        symbol = selectors;
      } else {
        symbol = g.selector.decode(bits);
        if (symbol < 0) return "a slice has an invalid selector code";
        if (symbol == selectors + g.history_size) {
          const int run = g.history_rle.decode(bits);
          if (run < 0) return "a slice has an invalid selector run code";
          rle_left = run == 63 ? std::uint64_t{bits.vlc(7)} + 3 : std::uint64_t(run) + 3;
          if (rle_left > total_blocks) return "a slice's selector run is longer than the image";
          symbol = selectors;
          --rle_left;
        }
      }
      int selector = 0;
      if (symbol >= selectors) {
        const int h_index = symbol - selectors;
        if (h_index >= g.history_size) return "a slice refers to a selector history entry beyond the buffer";
        selector = history[static_cast<std::size_t>(h_index)];
        if (h_index != 0) std::swap(history[static_cast<std::size_t>(h_index / 2)], history[static_cast<std::size_t>(h_index)]);
      } else {
        selector = symbol;
        history[rover++] = selector;
        if (rover == history.size()) rover = history.size() / 2;
      }
      if (endpoint >= endpoints || selector >= selectors)
        return "a slice refers to endpoint " + std::to_string(endpoint) + " or selector " + std::to_string(selector) +
               " beyond the codebooks (" + std::to_string(endpoints) + ", " + std::to_string(selectors) + ")";
      if (bits.overrun()) return "a slice is truncated";

      blocks[static_cast<std::size_t>(by) * static_cast<std::size_t>(bw) + static_cast<std::size_t>(bx)] = {
          static_cast<std::uint16_t>(endpoint), static_cast<std::uint16_t>(selector)};
    }
  }
  return "";
}

void etc1s_expand(const Etc1sGlobal& g, std::span<const Etc1sBlock> blocks, int w, int h, int by_begin, int by_end,
                  std::uint8_t* rgba, bool alpha) {
  const int bw = (w + 3) / 4;
  for (int by = by_begin; by < by_end; ++by)
    for (int bx = 0; bx < bw; ++bx) {
      const Etc1sBlock& b = blocks[static_cast<std::size_t>(by) * static_cast<std::size_t>(bw) + static_cast<std::size_t>(bx)];
      // The block's four colours: the 5-bit colour widened (c << 3 | c >> 2) plus each modifier.
      const Etc1sEndpoint& e = g.endpoints[b.endpoint];
      const auto& mod = kModifiers[e.inten];
      std::uint8_t colour[4][3];
      const int base[3] = {(e.r << 3) | (e.r >> 2), (e.g << 3) | (e.g >> 2), (e.b << 3) | (e.b >> 2)};
      for (int s = 0; s < 4; ++s)
        for (int c = 0; c < 3; ++c) colour[s][c] = static_cast<std::uint8_t>(std::clamp(base[c] + mod[static_cast<std::size_t>(s)], 0, 255));
      const auto& sel = g.selectors[b.selector];
      const int rows_in = std::min(4, h - by * 4), cols_in = std::min(4, w - bx * 4);
      for (int y = 0; y < rows_in; ++y)
        for (int x = 0; x < cols_in; ++x) {
          const int s = (sel[static_cast<std::size_t>(y)] >> (2 * x)) & 3;
          std::uint8_t* p = rgba + ((static_cast<std::size_t>(by) * 4 + y) * static_cast<std::size_t>(w) + bx * 4 + x) * 4;
          if (alpha) {
            p[3] = colour[s][1];
          } else {
            p[0] = colour[s][0];
            p[1] = colour[s][1];
            p[2] = colour[s][2];
            p[3] = 255;
          }
        }
    }
}

}  // namespace softpbr::image::detail
