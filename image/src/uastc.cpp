// UASTC blocks to RGBA8 (see uastc.h). Section names are those of the UASTC Texture
// Specification; "ASTC §" are the KHR Data Format Specification 1.3's.
#include "uastc.h"

#include <array>

namespace softpbr::image::detail {

namespace {

// One UASTC mode ("Mode table"). Endpoint and weight ranges are ASTC's range indices
// (ASTC §23.11, Table 94: 0 → 2 levels … 20 → 256 levels). Every UASTC weight range is a
// power of two, so weights are plain bit fields.
struct Mode {
  int subsets;         // partitions (1..3)
  int planes;          // 2: dual plane, the second plane's channel given by ccs
  int comps;           // 2 (luminance-alpha, CEM 4), 3 (RGB, CEM 8), 4 (RGBA, CEM 12)
  int endpoint_range;  // ASTC range of the endpoint values
  int weight_bits;     // bits a weight (1..5)
  int hint_bits;       // BC1/ETC1/ETC2 transcoding hints after the mode code, skipped here
  int pattern_bits;    // bits of the common partition pattern's index (0: one subset)
  int ccs_bits;        // bits of the dual plane's channel selector (0: fixed or one plane)
};

// Modes 0–18 (mode 8, solid colour, is handled apart). The hint bits are the sum of the
// fields the specification lists per mode: BC1 hints (1 or 2 bits), ETC1 flip, diff and
// two intensities (8), the ETC1 bias (5) where present, ETC2 alpha hints (8) in alpha modes.
constexpr std::array<Mode, 19> kModes = {{
    {1, 1, 3, 19, 4, 15, 0, 0},  // 0: RGB, 1 subset, trits + 6 bits
    {1, 1, 3, 20, 2, 15, 0, 0},  // 1: RGB, 8-bit endpoints, 2-bit weights
    {2, 1, 3, 8, 3, 15, 5, 0},   // 2: RGB, 2 subsets
    {3, 1, 3, 7, 2, 15, 4, 0},   // 3: RGB, 3 subsets
    {2, 1, 3, 12, 2, 15, 5, 0},  // 4: RGB, 2 subsets
    {1, 1, 3, 20, 3, 15, 0, 0},  // 5: RGB, 8-bit endpoints, 3-bit weights
    {1, 2, 3, 18, 2, 15, 0, 2},  // 6: RGB, dual plane
    {2, 1, 3, 12, 2, 15, 5, 0},  // 7: RGB, 2 subsets (BC7's 3-subset patterns)
    {0, 0, 0, 0, 0, 0, 0, 0},    // 8: solid colour
    {2, 1, 4, 8, 2, 23, 5, 0},   // 9: RGBA, 2 subsets
    {1, 1, 4, 13, 4, 17, 0, 0},  // 10: RGBA
    {1, 2, 4, 13, 2, 17, 0, 2},  // 11: RGBA, dual plane
    {1, 1, 4, 19, 3, 17, 0, 0},  // 12: RGBA
    {1, 2, 4, 20, 1, 23, 0, 2},  // 13: RGBA, dual plane, 1-bit weights
    {1, 1, 4, 20, 2, 23, 0, 0},  // 14: RGBA
    {1, 1, 2, 20, 4, 23, 0, 0},  // 15: luminance-alpha
    {2, 1, 2, 20, 2, 23, 5, 0},  // 16: luminance-alpha, 2 subsets
    {1, 2, 2, 20, 2, 23, 0, 0},  // 17: luminance-alpha, dual plane (alpha on the second)
    {1, 1, 3, 11, 5, 15, 0, 0},  // 18: RGB, 5-bit weights
}};

// "Mode encoding": the mode is a prefix code at bit 0, 2 to 7 bits long, read LSB first.
// {code, length} for modes 0–18, then the reserved code (mode 19, not decodable).
constexpr std::array<std::array<int, 2>, 20> kModeCodes = {{
    {0x1, 4},  {0x35, 6}, {0x1D, 5}, {0x3, 5},  {0x13, 5}, {0xB, 5},  {0x1B, 5},
    {0x7, 5},  {0x17, 5}, {0xF, 5},  {0x2, 3},  {0x0, 2},  {0x6, 3},  {0x1F, 5},
    {0xD, 5},  {0x5, 7},  {0x15, 6}, {0x25, 6}, {0x9, 4},  {0x45, 7},
}};

// The mode of each value of a block's low 7 bits: every code extended by all its suffixes.
constexpr std::array<std::uint8_t, 128> mode_lookup() {
  std::array<std::uint8_t, 128> t{};
  for (int m = 0; m < 20; ++m)
    for (int rest = 0; rest < (1 << (7 - kModeCodes[m][1])); ++rest)
      t[static_cast<std::size_t>(kModeCodes[m][0] | (rest << kModeCodes[m][1]))] = static_cast<std::uint8_t>(m);
  return t;
}
constexpr std::array<std::uint8_t, 128> kModeOfCode = mode_lookup();

// "Partition pattern tables": the ASTC partition seeds of the common patterns. Modes 2, 4,
// 9 and 16 index the 30 two-subset patterns, mode 3 the 11 three-subset ones, mode 7 the 19
// two-subset ASTC patterns that match BC7 three-subset ones.
constexpr std::array<int, 30> kSeeds2 = {28,  20,  16,  29,  91,  9,   107, 72,  149, 204, 50,  114, 496, 17,  78,
                                         39,  252, 828, 43,  156, 116, 210, 476, 273, 684, 359, 246, 195, 694, 524};
constexpr std::array<int, 11> kSeeds3 = {260, 74, 32, 156, 183, 15, 745, 0, 335, 902, 254};
constexpr std::array<int, 19> kSeedsMode7 = {36,  48,  61,  137, 161, 183, 226, 281, 302, 307,
                                             479, 495, 593, 594, 605, 799, 812, 988, 993};

// ASTC §23.11, Table 94: {bits, trits, quints} of each range.
constexpr std::array<std::array<int, 3>, 21> kRanges = {{
    {1, 0, 0}, {0, 1, 0}, {2, 0, 0}, {0, 0, 1}, {1, 1, 0}, {3, 0, 0}, {1, 0, 1},
    {2, 1, 0}, {4, 0, 0}, {2, 0, 1}, {3, 1, 0}, {5, 0, 0}, {3, 0, 1}, {4, 1, 0},
    {6, 0, 0}, {4, 0, 1}, {5, 1, 0}, {7, 0, 0}, {5, 0, 1}, {6, 1, 0}, {8, 0, 0},
}};

// A little-endian 128-bit block read LSB first. Reads beyond bit 128 give zeros (no
// UASTC mode's fields reach that far; the guard keeps a reader inside the block anyway).
class BlockBits {
 public:
  explicit BlockBits(const std::uint8_t* block) {
    for (int i = 15; i >= 0; --i) bits_ = (bits_ << 8) | block[i];
  }
  int read(int count) {
    if (pos_ >= 128) return 0;
    const int v = static_cast<int>((bits_ >> pos_) & ((1u << count) - 1));
    pos_ += count;
    return v;
  }
  void skip(int count) { pos_ += count; }

 private:
  unsigned __int128 bits_ = 0;
  int pos_ = 0;
};

// ASTC §23.15: a weight of a power-of-two range to 0..64 (bits replicated to 6, then
// values above 32 raised by one), tabled by bit count (1..5) and value.
constexpr int unquantize_weight(int bits, int w) {
  int v = 0;
  switch (bits) {
    case 1: v = w ? 63 : 0; break;
    case 2: v = (w << 4) | (w << 2) | w; break;
    case 3: v = (w << 3) | w; break;
    case 4: v = (w << 2) | (w >> 2); break;
    default: v = (w << 1) | (w >> 4); break;
  }
  return v > 32 ? v + 1 : v;
}
constexpr std::array<std::array<std::uint8_t, 32>, 6> weight_table() {
  std::array<std::array<std::uint8_t, 32>, 6> t{};
  for (int bits = 1; bits <= 5; ++bits)
    for (int w = 0; w < (1 << bits); ++w)
      t[static_cast<std::size_t>(bits)][static_cast<std::size_t>(w)] = static_cast<std::uint8_t>(unquantize_weight(bits, w));
  return t;
}
constexpr auto kWeights = weight_table();

// ASTC §23.16: an 8-bit endpoint and a weight to the decoded 8-bit value. The endpoints
// are widened to 16 bits by replication (×257, decode mode "linear" — what Basis Universal's
// transcoder writes for RGBA32 whatever the transfer function), blended, and the top byte kept.
// `l` and `h` are the endpoints already widened (× 257).
int interpolate(int l, int h, int w) { return ((l * (64 - w) + h * w + 32) >> 6) >> 8; }

// ASTC's partition hash (§23.21).
constexpr std::uint32_t hash52(std::uint32_t p) {
  p ^= p >> 15;
  p -= p << 17;
  p += p << 7;
  p += p << 4;
  p ^= p >> 5;
  p += p << 16;
  p ^= p >> 7;
  p ^= p >> 3;
  p ^= p << 6;
  p ^= p >> 17;
  return p;
}

constexpr int partition_of(int seed, int x, int y, int partitions) {
  // A block of fewer than 31 texels doubles its coordinates (4×4 here).
  x <<= 1;
  y <<= 1;
  seed += (partitions - 1) * 1024;
  const std::uint32_t rnum = hash52(static_cast<std::uint32_t>(seed));
  std::array<int, 12> s{};
  for (int i = 0; i < 8; ++i) s[static_cast<std::size_t>(i)] = static_cast<int>((rnum >> (4 * i)) & 0xF);
  s[8] = static_cast<int>((rnum >> 18) & 0xF);
  s[9] = static_cast<int>((rnum >> 22) & 0xF);
  s[10] = static_cast<int>((rnum >> 26) & 0xF);
  s[11] = static_cast<int>(((rnum >> 30) | (rnum << 2)) & 0xF);
  for (int& v : s) v *= v;
  int sh1 = 0, sh2 = 0;
  if (seed & 1) {
    sh1 = (seed & 2) ? 4 : 5;
    sh2 = partitions == 3 ? 6 : 5;
  } else {
    sh1 = partitions == 3 ? 6 : 5;
    sh2 = (seed & 2) ? 4 : 5;
  }
  const int sh3 = (seed & 0x10) ? sh1 : sh2;
  for (int i = 0; i < 8; ++i) s[static_cast<std::size_t>(i)] >>= (i & 1) ? sh2 : sh1;
  for (int i = 8; i < 12; ++i) s[static_cast<std::size_t>(i)] >>= sh3;
  // z = 0 in a 2D block: the z terms (s[8..11]) drop out.
  const int a = static_cast<int>((static_cast<std::uint32_t>(s[0] * x + s[1] * y) + (rnum >> 14)) & 0x3F);
  const int b = static_cast<int>((static_cast<std::uint32_t>(s[2] * x + s[3] * y) + (rnum >> 10)) & 0x3F);
  int c = static_cast<int>((static_cast<std::uint32_t>(s[4] * x + s[5] * y) + (rnum >> 6)) & 0x3F);
  if (partitions < 3) c = 0;
  if (a >= b && a >= c) return 0;
  if (b >= c) return 1;
  return 2;
}

// The 4×4 patterns of each common-pattern table, computed once at compile time.
template <std::size_t N>
constexpr std::array<std::array<std::uint8_t, 16>, N> patterns(const std::array<int, N>& seeds, int partitions) {
  std::array<std::array<std::uint8_t, 16>, N> out{};
  for (std::size_t p = 0; p < N; ++p)
    for (int i = 0; i < 16; ++i) out[p][static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(partition_of(seeds[p], i & 3, i >> 2, partitions));
  return out;
}
constexpr auto kPatterns2 = patterns(kSeeds2, 2);
constexpr auto kPatterns3 = patterns(kSeeds3, 3);
constexpr auto kPatternsMode7 = patterns(kSeedsMode7, 2);

constexpr int unquantize_endpoint(int range, int value) {
  const int n = kRanges[static_cast<std::size_t>(range)][0], trits = kRanges[static_cast<std::size_t>(range)][1],
            quints = kRanges[static_cast<std::size_t>(range)][2];
  if (!trits && !quints) {  // bits only: replicate to 8 bits
    int v = value << (8 - n);
    for (int have = n; have < 8; have += n) v |= v >> n;
    return v & 0xFF;
  }
  // 3 and 5 levels (no bits; not used by UASTC's endpoints): evenly spread.
  if (n == 0) return trits ? (value * 255 + 1) / 2 : (value * 255 + 2) / 4;
  // Table 95: D the trit or quint, bits (b..a) of the low part; A is bit a repeated over 9
  // bits, B the low bits scattered, C the scale. Then T = D·C + B, T ^= A, T = (A & 0x80) | (T >> 2).
  const int d = value >> n;
  const int low = value & ((1 << n) - 1);
  const int a = (low & 1) ? 0x1FF : 0;
  const int bit_b = (low >> 1) & 1, bit_c = (low >> 2) & 1, bit_d = (low >> 3) & 1, bit_e = (low >> 4) & 1,
            bit_f = (low >> 5) & 1;
  int b = 0, c = 0;
  if (trits) {
    switch (n) {
      case 1: c = 204; break;
      case 2: b = bit_b * 0x116; c = 93; break;  // b000b0bb0
      case 3: b = bit_c * 0x10A + bit_b * 0x85; c = 44; break;  // cb000cbcb
      case 4: b = ((low >> 1) & 7) * 0x41; c = 22; break;  // dcb000dcb
      case 5: b = ((low >> 1) & 0xF) * 0x20 + (bit_e << 1 | bit_d); c = 11; break;  // edcb000ed
      default: b = ((low >> 1) & 0x1F) * 0x10 + bit_f; c = 5; break;  // fedcb000f
    }
  } else {
    switch (n) {
      case 1: c = 113; break;
      case 2: b = bit_b * 0x10C; c = 54; break;  // b0000bb00
      case 3: b = (bit_c << 8) | (bit_b << 7) | (bit_c << 2) | (bit_b << 1) | bit_c; c = 26; break;  // cb0000cbc
      case 4: b = (((low >> 1) & 7) << 6) | (bit_d << 1) | bit_c; c = 13; break;  // dcb0000dc
      default: b = (((low >> 1) & 0xF) << 5) | bit_e; c = 6; break;  // edcb0000e
    }
  }
  int t = d * c + b;
  t ^= a;
  return (a & 0x80) | (t >> 2);
}

// Every range's values (BISE index → 0..255), computed at compile time.
constexpr std::array<std::array<std::uint8_t, 256>, 21> endpoint_table() {
  std::array<std::array<std::uint8_t, 256>, 21> t{};
  for (int range = 0; range < 21; ++range) {
    const int levels = (1 + 2 * kRanges[static_cast<std::size_t>(range)][1] + 4 * kRanges[static_cast<std::size_t>(range)][2])
                       << kRanges[static_cast<std::size_t>(range)][0];
    for (int v = 0; v < levels && v < 256; ++v)
      t[static_cast<std::size_t>(range)][static_cast<std::size_t>(v)] = static_cast<std::uint8_t>(unquantize_endpoint(range, v));
  }
  return t;
}
constexpr auto kEndpoints = endpoint_table();

}  // namespace

int astc_partition(int seed, int x, int y, int partitions) { return partition_of(seed, x, y, partitions); }

int astc_unquantize_endpoint(int range, int value) { return unquantize_endpoint(range, value); }

bool decode_uastc_block(const std::uint8_t* block, std::uint8_t* rgba) {
  BlockBits bits(block);
  const int mode_index = kModeOfCode[block[0] & 127];
  if (mode_index >= 19) return false;  // the reserved code
  bits.skip(kModeCodes[static_cast<std::size_t>(mode_index)][1]);

  if (mode_index == 8) {  // "Mode 8: solid colour": RGBA8, then ETC1 hints
    std::uint8_t c[4];
    for (std::uint8_t& v : c) v = static_cast<std::uint8_t>(bits.read(8));
    for (int i = 0; i < 16; ++i)
      for (int k = 0; k < 4; ++k) rgba[i * 4 + k] = c[k];
    return true;
  }

  const Mode& m = kModes[static_cast<std::size_t>(mode_index)];
  bits.skip(m.hint_bits);

  // The partition of each texel: the common pattern's, from its ASTC seed.
  std::array<std::uint8_t, 16> part{};
  if (m.subsets > 1) {
    const std::size_t pattern = static_cast<std::size_t>(bits.read(m.pattern_bits));
    if (mode_index == 3) {
      if (pattern >= kPatterns3.size()) return false;
      part = kPatterns3[pattern];
    } else if (mode_index == 7) {
      if (pattern >= kPatternsMode7.size()) return false;
      part = kPatternsMode7[pattern];
    } else {
      if (pattern >= kPatterns2.size()) return false;
      part = kPatterns2[pattern];
    }
  }
  // Dual plane: the channel on the second plane (mode 17: alpha).
  int ccs = -1;
  if (m.planes == 2) ccs = m.ccs_bits ? bits.read(m.ccs_bits) : 3;

  // "Endpoint encoding": the trits (5 to 8 bits, base 3) or quints (3 to 7 bits, base 5)
  // of all values first, in groups, the last group shortened; then each value's low bits.
  const int values = m.comps * 2 * m.subsets;
  const auto [ep_bits, ep_trits, ep_quints] = kRanges[static_cast<std::size_t>(m.endpoint_range)];
  std::array<int, 18> tq{};  // each value's trit or quint
  if (ep_trits || ep_quints) {
    const int group = ep_trits ? 5 : 3, base = ep_trits ? 3 : 5;
    // Bits of a group of k digits: ⌈log₂ base^k⌉.
    static constexpr std::array<int, 6> kTritBits = {0, 2, 4, 5, 7, 8};
    static constexpr std::array<int, 4> kQuintBits = {0, 3, 5, 7};
    for (int first = 0; first < values; first += group) {
      const int k = values - first < group ? values - first : group;
      int packed = bits.read(ep_trits ? kTritBits[static_cast<std::size_t>(k)] : kQuintBits[static_cast<std::size_t>(k)]);
      for (int j = 0; j < k; ++j) {
        tq[static_cast<std::size_t>(first + j)] = packed % base;
        packed /= base;
      }
    }
  }
  std::array<int, 18> endpoint{};  // unquantized, in the order (c0 low, c0 high, c1 low, …) per subset
  for (int i = 0; i < values; ++i) {
    const int low = bits.read(ep_bits);
    endpoint[static_cast<std::size_t>(i)] =
        kEndpoints[static_cast<std::size_t>(m.endpoint_range)][static_cast<std::size_t>((tq[static_cast<std::size_t>(i)] << ep_bits) | low)];
  }

  // "Weight encoding": texel order, plane 0 and 1 interleaved; the first texel of each
  // subset (its anchor) has one bit less, its top bit being 0.
  std::array<bool, 16> anchor{};
  std::array<bool, 3> seen{};
  for (int i = 0; i < 16; ++i)
    if (!seen[part[static_cast<std::size_t>(i)]]) {
      seen[part[static_cast<std::size_t>(i)]] = true;
      anchor[static_cast<std::size_t>(i)] = true;
    }
  std::array<int, 32> weight{};
  const auto& weights = kWeights[static_cast<std::size_t>(m.weight_bits)];
  for (int i = 0; i < 16; ++i)
    for (int p = 0; p < m.planes; ++p) {
      const int w = bits.read(anchor[static_cast<std::size_t>(i)] ? m.weight_bits - 1 : m.weight_bits);
      weight[static_cast<std::size_t>(i * 2 + p)] = weights[static_cast<std::size_t>(w)];
    }

  // Each subset's endpoints in RGBA order, widened to 16 bits: luminance-alpha endpoints
  // (L, A) give L to R, G and B; RGB modes have alpha 255 at both ends (which blends to 255).
  std::array<std::array<int, 4>, 3> lo{}, hi{};
  for (int sub = 0; sub < m.subsets; ++sub)
    for (int k = 0; k < 4; ++k) {
      const int comp = m.comps == 2 ? (k == 3 ? 1 : 0) : k;
      const bool present = comp < m.comps;
      const std::size_t at = static_cast<std::size_t>(sub * m.comps * 2 + comp * 2);
      lo[static_cast<std::size_t>(sub)][static_cast<std::size_t>(k)] = (present ? endpoint[at] : 255) * 257;
      hi[static_cast<std::size_t>(sub)][static_cast<std::size_t>(k)] = (present ? endpoint[at + 1] : 255) * 257;
    }
  for (int i = 0; i < 16; ++i) {
    const std::size_t sub = part[static_cast<std::size_t>(i)];
    const int w0 = weight[static_cast<std::size_t>(i * 2)], w1 = weight[static_cast<std::size_t>(i * 2 + 1)];
    for (int k = 0; k < 4; ++k) {
      const int w = k == ccs ? w1 : w0;
      rgba[i * 4 + k] = static_cast<std::uint8_t>(interpolate(lo[sub][static_cast<std::size_t>(k)], hi[sub][static_cast<std::size_t>(k)], w));
    }
  }
  return true;
}

}  // namespace softpbr::image::detail
