// Texture lookups kL lanes at a time (8 with AVX2, 16 with AVX-512), compiled once per
// target (texture.cpp includes it through softpbr/simd/foreach_target.h; no include guard,
// no header included here), and once more for AVX-512 with VBMI (SOFTPBR_TARGET_VBMI 1:
// namespace avx512vbmi, the table lookups by byte permutes). Only the copies with 256-bit
// vectors or wider define the kernel (SOFTPBR_TARGET_AVX: avx2, avx512, avx512vbmi);
// texture.cpp runs its scalar code elsewhere. The lane operations on plain vectors (mask
// bits, gathers, table lookups, byte permutes) are simd's (`lanes::`).
//
// The kernel is texture.cpp's scalar fast path (Lookup::sample_fast: an 8-bit texture whose
// sides are powers of two, both wraps Repeat, every filter Linear) on kL lanes: every
// lane goes through the IEEE operations the scalar code applies to it, in the same order
// (-ffp-contract=off, no target enables FMA); branches become selects, and a lane's result
// is the one its branch of the scalar code computes. Where the scalar code skips work
// (a level it does not read, a probe it does not take), the kernel computes it and
// discards it by a select, or adds 0 to a sum (of non-negative values: 8-bit texels
// decode to +0 … 1, so x + 0 = x exactly). Lanes beyond `n` read zeros and are not stored.

namespace softpbr::raster::detail::SOFTPBR_TARGET_NS {

#if SOFTPBR_TARGET_AVX

namespace texture_lanes {

namespace lanes = simd::SOFTPBR_TARGET_NS;
using lanes::all_lanes;
using lanes::any_lane;

// kL lanes: 16 where the target has AVX-512 (its 512-bit registers), else 8.
#if SOFTPBR_TARGET_AVX512
inline constexpr int kL = 16;
#else
inline constexpr int kL = 8;
#endif
typedef float FV __attribute__((vector_size(4 * kL)));
typedef std::int32_t IV __attribute__((vector_size(4 * kL)));

inline FV splat(float x) { return x - FV{}; }  // a bare broadcast (see Lanes(float))
inline IV splat_int(std::int32_t x) { return IV{} + x; }
// m ? a : b per lane (m all ones or zeros, as comparisons give).
inline FV select(IV m, FV a, FV b) { return (FV)((m & (IV)a) | (~m & (IV)b)); }
inline IV select(IV m, IV a, IV b) { return (m & a) | (~m & b); }
inline FV to_float(IV i) { return __builtin_convertvector(i, FV); }
inline IV to_int(FV x) { return __builtin_convertvector(x, IV); }  // towards zero
inline FV sqrt(FV x) { return simd::sqrt(simd::Lanes<kL, SOFTPBR_ISA>(x)).v; }

// finite_or_zero: x − x is 0 only for finite x.
inline FV finite_or_zero(FV x) { return select((x - x) == 0.0f, x, FV{}); }
// std::clamp(v, lo, hi): v < lo ? lo : (hi < v ? hi : v).
inline FV clamp(FV v, float lo, float hi) { return select(v < lo, splat(lo), select(splat(hi) < v, splat(hi), v)); }
// coordinate(): clamped to ±2^16.
inline FV coordinate(FV x) { return clamp(finite_or_zero(x), -kMaxCoordinate, kMaxCoordinate); }

// floor_of() per lane (the same preconditions: |x| < 2^31, x ≠ −0).
struct FloorL {
  IV i;
  FV f;
};
inline FloorL floor_of(FV x) {
  IV i = to_int(x);
  i = i + (to_float(i) > x);  // a true mask is −1
  return {i, to_float(i)};
}

// log2_of()'s polynomial per lane, from the exponent e and the significand's bits.
inline FV log2_tail(IV e, IV bits) {
  FV m = (FV)((bits & 0x007fffff) | 0x3f800000);  // [1, 2)
  const IV above = m > 1.41421356f;
  m = select(above, m * 0.5f, m);
  e = e - above;
  const FV s = (m - 1.0f) / (m + 1.0f);
  const FV s2 = s * s;
  FV p = splat(1.0f / 9.0f);
  p = p * s2 + 1.0f / 7.0f;
  p = p * s2 + 1.0f / 5.0f;
  p = p * s2 + 1.0f / 3.0f;
  p = p * s2 + 1.0f;
  constexpr float kTwoOverLn2 = 2.88539008f;  // 2 / ln 2
  return to_float(e) + s * p * kTwoOverLn2;
}

// log2_of() per lane: the same selects and the same polynomial. Where every lane is a
// normal float (FLT_MIN ≤ x < ∞, as a lookup's footprint is unless a derivative is 0),
// the selects of the special cases are identities and are skipped.
inline FV log2_of(FV x) {
  const float inf = std::numeric_limits<float>::infinity();
  const IV bits = (IV)x;
  if (all_lanes((x >= std::numeric_limits<float>::min()) & (x < inf))) return log2_tail((bits >> 23) - 127, bits);
  const IV subnormal = x < std::numeric_limits<float>::min();
  const FV xn = select(subnormal, x * 16777216.0f, x);  // 2^24
  const IV nbits = (IV)xn;
  const IV e = select(subnormal, splat_int(-24), IV{}) + (((nbits >> 23) & 0xff) - 127);
  FV r = log2_tail(e, nbits);
  r = select(x == inf, splat(inf), r);
  r = select(x == 0.0f, splat(-inf), r);
  return select(!(x >= 0.0f), splat(std::numeric_limits<float>::quiet_NaN()), r);  // NaN, negatives
}

struct RgbaV {
  FV c[4];
};

// A level per lane: the masks of its sides (powers of two), log₂ of its width, its first
// texel, its sides as floats.
struct LevelLanes {
  IV wmask, hmask, wshift, offset;
  FV fw, fh;
};
inline LevelLanes level_lanes(const LaneTexture& t, IV d) {
  LevelLanes r;
  if (all_lanes(d == d[0])) {
    const Texture::Level& lv = t.levels[d[0]];
    r.wmask = splat_int(lv.width - 1);
    r.hmask = splat_int(lv.height - 1);
    r.wshift = splat_int(std::countr_zero(static_cast<unsigned>(lv.width)));
    r.offset = splat_int(static_cast<std::int32_t>(lv.offset));
    r.fw = splat(static_cast<float>(lv.width));
    r.fh = splat(static_cast<float>(lv.height));
    return r;
  }
  for (int i = 0; i < kL; ++i) {
    const Texture::Level& lv = t.levels[d[i]];
    r.wmask[i] = lv.width - 1;
    r.hmask[i] = lv.height - 1;
    r.wshift[i] = std::countr_zero(static_cast<unsigned>(lv.width));
    r.offset[i] = static_cast<std::int32_t>(lv.offset);
    r.fw[i] = static_cast<float>(lv.width);
    r.fh[i] = static_cast<float>(lv.height);
  }
  return r;
}

#if SOFTPBR_TARGET_AVX512
// 16 texel words (RGBA8), or 64 bytes, in one register.
using Words = simd::bits512_t;

// The texel words at kL indices into the texel array.
inline Words texel_words(const LaneTexture& t, IV index) { return lanes::gather_words(t.texels, index); }
// The texel words at index and index + 1 in each lane (the caller's index + 1 must not
// leave the row: no lane wraps), one 8-byte load a lane: half the loads of two
// texel_words(). Bilinear's footprint is two such pairs. Zen 4, BM_TextureLookups:
// trilinear −7%, 16× anisotropic −12%.
inline void texel_word_pairs(const LaneTexture& t, IV index, Words& first, Words& second) {
  lanes::gather_word_pairs(t.texels, index, first, second);
}

#if SOFTPBR_TARGET_VBMI
// The colour table applied to every byte of the 16 words at once (lookup_bytes256: with
// VBMI, byte permutes of the table in registers); the entry's bytes are then gathered
// into channel ch's floats. The table is held as four planes (LaneTexture::planes: byte k
// of entry c at [256 k + c]). Pure data movement: the table's floats, bit for bit. 13
// instructions for the planes, 3 a channel: against 19 a channel for lookup_floats256.
struct DecodedBytes {
  Words b[4];  // b[k]: byte k of the entry of each of the 64 codes
};
inline DecodedBytes decode_bytes(const LaneTexture& t, Words w) {
  DecodedBytes d;
  for (int k = 0; k < 4; ++k) d.b[k] = lanes::lookup_bytes256(t.planes + 256 * k, w);
  return d;
}
// Channel ch's floats: lane i's bytes 0–3 from b[0..3] at 4i + ch.
inline FV channel_floats(const DecodedBytes& d, int ch) {
  // Byte 4i + j of the index: 4i + ch, plus 64 (the second source) for j = 1 and 3.
  typedef std::uint8_t Bytes __attribute__((vector_size(64)));
  const IV lane = {0x00000000, 0x04040404, 0x08080808, 0x0c0c0c0c, 0x10101010, 0x14141414, 0x18181818, 0x1c1c1c1c,
                   0x20202020, 0x24242424, 0x28282828, 0x2c2c2c2c, 0x30303030, 0x34343434, 0x38383838, 0x3c3c3c3c};
  const Words idx = (Words)((Bytes)lane + (Bytes)splat_int(0x40004000 + 0x01010101 * ch));
  const Words x = lanes::permute_bytes(d.b[0], idx, d.b[1]);  // bytes 0, 1
  const Words y = lanes::permute_bytes(d.b[2], idx, d.b[3]);  // bytes 2, 3
  return (FV)lanes::blend_bytes(0xccccccccccccccccull, x, y);
}
// The colour channels of four texel-word vectors decoded together: their 192 colour codes
// (the alpha codes left out) gathered into three registers by byte permutes, each
// decoded by decode_bytes(), and the floats assembled from the four byte planes by
// unpacks. Register k's codes are ordered so that the unpacks give whole channels:
// within each 128-bit block q, bytes 4m … 4m + 3 hold lanes 4q … 4q + 3 of its m-th
// channel, where the channels are (word vector, channel) pairs n = 4k + m, (n / 3, n % 3).
// 3 + 3 · 13 + 3 · 8 = 66 instructions, against 4 · (13 + 3 · 3) = 88 by decode_words();
// pure data movement, the same floats.
struct RgbCodeOrder {
  std::uint8_t idx[3][64];
};
inline constexpr RgbCodeOrder kRgbCodeOrder = [] {
  RgbCodeOrder o{};
  for (int k = 0; k < 3; ++k)
    for (int q = 0; q < 4; ++q)
      for (int m = 0; m < 4; ++m)
        for (int i = 0; i < 4; ++i) {
          const int n = 4 * k + m, word = n / 3, ch = n % 3, first = 4 * k / 3;
          o.idx[k][16 * q + 4 * m + i] = static_cast<std::uint8_t>(4 * (4 * q + i) + ch + (word == first ? 0 : 64));
        }
  return o;
}();
inline void decode_rgb4(const LaneTexture& t, const Words (&w)[4], RgbaV (&c)[4]) {
  for (int k = 0; k < 3; ++k) {
    const int first = 4 * k / 3;  // the register's codes come from word vectors first and first + 1
    const Words codes = lanes::permute_bytes(w[first], lanes::load_bits512(kRgbCodeOrder.idx[k]), w[first + 1]);
    const DecodedBytes d = decode_bytes(t, codes);
    const Words t0 = lanes::unpack_lo8(d.b[0], d.b[1]), t1 = lanes::unpack_hi8(d.b[0], d.b[1]);
    const Words t2 = lanes::unpack_lo8(d.b[2], d.b[3]), t3 = lanes::unpack_hi8(d.b[2], d.b[3]);
    const Words f[4] = {lanes::unpack_lo16(t0, t2), lanes::unpack_hi16(t0, t2), lanes::unpack_lo16(t1, t3),
                     lanes::unpack_hi16(t1, t3)};
    for (int m = 0; m < 4; ++m) c[(4 * k + m) / 3].c[(4 * k + m) % 3] = (FV)f[m];
  }
  for (int j = 0; j < 4; ++j) c[j].c[3] = FV{};
}
#endif
#endif  // SOFTPBR_TARGET_AVX512

#if SOFTPBR_TARGET_AVX512
// kL texel words (RGBA8) decoded: colour through the texture's table, alpha to k/255;
// only the channels in kCh (bit c: channel c), the others 0. Table lookups in registers:
// the fetch at 16 lanes was ~80% table and byte loads.
template <unsigned kCh>
inline RgbaV decode_words(const LaneTexture& t, Words w) {
  RgbaV r;
#if SOFTPBR_TARGET_VBMI
  constexpr bool kColour = (kCh & Texture::kRgb) != 0;
  DecodedBytes d{};
  if constexpr (kColour) d = decode_bytes(t, w);
#endif
  for (int ch = 0; ch < 4; ++ch) {
    if (!(kCh >> ch & 1)) {
      r.c[ch] = FV{};
    } else if (ch == 3) {
      // The alpha table's entries are k/255 in float, one rounding: so is this.
      r.c[3] = to_float(((IV)w >> 24) & 0xff) / 255.0f;
    } else {
#if SOFTPBR_TARGET_VBMI
      r.c[ch] = channel_floats(d, ch);
#else
      r.c[ch] = lanes::lookup_floats256(t.rgb, (IV)w >> (8 * ch));
#endif
    }
  }
  return r;
}
#else
// kL texels (RGBA8, by index into the texel array) decoded: colour through the
// texture's table, alpha to k/255; only the channels in kCh (bit c: channel c), the
// others 0. (The AVX-512 copies load words and decode them: footprint_words, decode_four.)
template <unsigned kCh>
inline RgbaV texels(const LaneTexture& t, IV index) {
  // One by one: on Zen 3 this is faster than AVX2's gathers (one for the texels and four
  // for the tables: 50 against 43 ns a lookup in a micro benchmark, though half the
  // instructions).
  RgbaV r;
  alignas(64) std::int32_t at[kL];
  std::memcpy(at, &index, sizeof at);
  alignas(64) float c[4][kL];
  for (int i = 0; i < kL; ++i) {
    const std::uint8_t* p = t.texels + static_cast<std::size_t>(at[i]) * 4;
    if constexpr ((kCh & 1) != 0) c[0][i] = t.rgb[p[0]];
    if constexpr ((kCh & 2) != 0) c[1][i] = t.rgb[p[1]];
    if constexpr ((kCh & 4) != 0) c[2][i] = t.rgb[p[2]];
    if constexpr ((kCh & 8) != 0) c[3][i] = t.alpha[p[3]];
  }
  for (int ch = 0; ch < 4; ++ch) {
    if (kCh >> ch & 1) std::memcpy(&r.c[ch], c[ch], sizeof(FV));
    else r.c[ch] = FV{};
  }
  return r;
}
#endif  // SOFTPBR_TARGET_AVX512

// Lookup::bilinear_repeat()'s weights of the four texels, per lane.
struct Weights {
  FV ax, ay;
};
// The four texels' colours weighted (bilinear_repeat's sums, the channels in kCh).
template <unsigned kCh>
inline RgbaV filter(const RgbaV& c00, const RgbaV& c10, const RgbaV& c01, const RgbaV& c11, Weights wt) {
  const FV bx = 1.0f - wt.ax, by = 1.0f - wt.ay;
  RgbaV out;
  for (int ch = 0; ch < 4; ++ch) {
    if (!(kCh >> ch & 1)) {
      out.c[ch] = FV{};
      continue;
    }
    const FV top = c00.c[ch] * bx + c10.c[ch] * wt.ax;
    const FV bottom = c01.c[ch] * bx + c11.c[ch] * wt.ax;
    out.c[ch] = top * by + bottom * wt.ay;
  }
  return out;
}

// Lookup::bilinear_repeat()'s texel indices per lane, each at its own level: (ia, ja)
// and its neighbours (ib, jb), as rows and columns.
struct Footprint {
  IV ia, ib, row_a, row_b;
  IV wraps;  // lanes where ib is 0 (not ia + 1)
  Weights wt;
};
inline Footprint footprint_of(const LevelLanes& lv, FV cu, FV cv) {
  const FV x = cu * lv.fw, y = cv * lv.fh;
  const FV xs = x - 0.5f, ys = y - 0.5f;
  const FloorL x0 = floor_of(xs), y0 = floor_of(ys);
  Footprint f;
  f.wt = {xs - x0.f, ys - y0.f};  // exact
  // Powers of two: i & (w − 1) is repeat_index(i, w), (i + 1) & (w − 1) its neighbour.
  f.ia = x0.i & lv.wmask;
  const IV ja = y0.i & lv.hmask;
  f.ib = (f.ia + 1) & lv.wmask;
  f.wraps = f.ia == lv.wmask;
  const IV jb = (ja + 1) & lv.hmask;
  f.row_a = lv.offset + (ja << lv.wshift), f.row_b = lv.offset + (jb << lv.wshift);
  return f;
}

#if SOFTPBR_TARGET_AVX512
// The texel words of a footprint: at (ia, ja), (ib, ja), (ia, jb), (ib, jb).
inline void footprint_words(const LaneTexture& t, const Footprint& f, Words (&w)[4]) {
  if (!any_lane(f.wraps)) {
    // No lane wraps in x: each row's two texels are adjacent, one 8-byte load.
    texel_word_pairs(t, f.row_a + f.ia, w[0], w[1]);
    texel_word_pairs(t, f.row_b + f.ia, w[2], w[3]);
  } else {
    w[0] = texel_words(t, f.row_a + f.ia), w[1] = texel_words(t, f.row_a + f.ib);
    w[2] = texel_words(t, f.row_b + f.ia), w[3] = texel_words(t, f.row_b + f.ib);
  }
}
// Four texel-word vectors decoded (the channels in kCh).
template <unsigned kCh>
inline void decode_four(const LaneTexture& t, const Words (&w)[4], RgbaV (&c)[4]) {
#if SOFTPBR_TARGET_VBMI
  if constexpr (kCh == Texture::kRgb) return decode_rgb4(t, w, c);
#endif
  for (int j = 0; j < 4; ++j) c[j] = decode_words<kCh>(t, w[j]);
}
#endif

// Lookup::bilinear_repeat() per lane, each at its own level (the channels in kCh).
template <unsigned kCh>
inline RgbaV bilinear(const LaneTexture& t, const LevelLanes& lv, FV cu, FV cv) {
  const Footprint f = footprint_of(lv, cu, cv);
#if SOFTPBR_TARGET_AVX512
  Words w[4];
  footprint_words(t, f, w);
  RgbaV c[4];
  decode_four<kCh>(t, w, c);
  return filter<kCh>(c[0], c[1], c[2], c[3], f.wt);
#else
  const RgbaV c00 = texels<kCh>(t, f.row_a + f.ia), c10 = texels<kCh>(t, f.row_a + f.ib);
  const RgbaV c01 = texels<kCh>(t, f.row_b + f.ia), c11 = texels<kCh>(t, f.row_b + f.ib);
  return filter<kCh>(c00, c10, c01, c11, f.wt);
#endif
}

// Lookup::trilinear_repeat() per lane: level 0 where λ ≤ 0, the last level where λ ≥ q,
// else the blend of the two levels around λ.
template <unsigned kCh>
inline RgbaV trilinear(const LaneTexture& t, FV lod, FV u, FV v) {
  // coordinate() is the identity where every lane is within ±2^16 (NaN is not).
  const float k = kMaxCoordinate;
  const bool inside = all_lanes((u >= -k) & (u <= k) & (v >= -k) & (v <= k));
  FV cu = u, cv = v;
  if (!inside) cu = coordinate(u), cv = coordinate(v);
  const IV positive = lod > 0.0f;
  const IV between = positive & (lod < static_cast<float>(t.q));
  const FloorL f = floor_of(select(between, lod, splat(0.5f)));
  const IV d1 = select(between, f.i, select(positive, splat_int(t.q), IV{}));
#if SOFTPBR_TARGET_AVX512
  if (!any_lane(between)) return bilinear<kCh>(t, level_lanes(t, d1), cu, cv);
  // The two levels stage by stage (footprints, loads, decoding, sums), not one after the
  // other: two independent chains side by side in the instruction stream, which the
  // core overlaps (one level's chain alone is mostly latency).
  const Footprint fa = footprint_of(level_lanes(t, d1), cu, cv);
  const Footprint fb = footprint_of(level_lanes(t, select(between, d1 + 1, d1)), cu, cv);
  Words wa[4], wb[4];
  footprint_words(t, fa, wa);
  footprint_words(t, fb, wb);
  RgbaV ca[4], cb[4];
  decode_four<kCh>(t, wa, ca);
  decode_four<kCh>(t, wb, cb);
  const RgbaV a = filter<kCh>(ca[0], ca[1], ca[2], ca[3], fa.wt);
  const RgbaV b = filter<kCh>(cb[0], cb[1], cb[2], cb[3], fb.wt);
#else
  const RgbaV a = bilinear<kCh>(t, level_lanes(t, d1), cu, cv);
  if (!any_lane(between)) return a;
  const RgbaV b = bilinear<kCh>(t, level_lanes(t, select(between, d1 + 1, d1)), cu, cv);
#endif
  const FV w = lod - f.f;  // exact where it is used
  RgbaV out;
  for (int ch = 0; ch < 4; ++ch) out.c[ch] = select(between, a.c[ch] * (1.0f - w) + b.c[ch] * w, a.c[ch]);
  return out;
}

// clamp_lod(lod + finite_or_zero(bias)) with the batch's bias, 0.
inline FV clamp_lod(const LaneTexture& t, FV lod) { return clamp((lod + 0.0f) + t.lod_bias, t.min_lod, t.max_lod); }

// Lookup::sample_fast() per lane (the batch's bias is 0), the channels in kCh; kAniso
// false: for a sampler whose max_anisotropy is 1 (one probe per lane, no probe loop).
template <unsigned kCh, bool kAniso>
inline RgbaV sample_v(const LaneTexture& t, FV u, FV v, FV dudx, FV dvdx, FV dudy, FV dvdy) {
  // Lookup::footprint(): non-finite derivatives read as 0. Where every lane's px² + py²
  // is finite, so is every derivative (a non-finite one makes its square +∞ or NaN), and
  // finite_or_zero() is the identity there.
  FV px2, py2;
  auto squares = [&] {
    const FV ux = dudx * t.width, vx = dvdx * t.height, uy = dudy * t.width, vy = dvdy * t.height;
    px2 = ux * ux + vx * vx;
    py2 = uy * uy + vy * vy;
  };
  squares();
  if (!all_lanes(px2 + py2 < std::numeric_limits<float>::infinity())) {
    dudx = finite_or_zero(dudx);
    dvdx = finite_or_zero(dvdx);
    dudy = finite_or_zero(dudy);
    dvdy = finite_or_zero(dvdy);
    squares();
  }
  if (!kAniso) {
    // Isotropic: P_max alone, one square root. √ is monotonic and correctly rounded, so
    // √max(px², py²) is max(√px², √py²) (finite inputs: the squares are ≥ 0 or +∞, no NaN).
    const FV pmax = sqrt(select(px2 < py2, py2, px2));
    return trilinear<kCh>(t, clamp_lod(t, log2_of(pmax)), u, v);
  }
  const FV px = sqrt(px2);
  const FV py = sqrt(py2);
  const IV x_major = ~(px < py);
  const FV pmax = select(x_major, px, py), pmin = select(x_major, py, px);
  IV probes = splat_int(1);
  if (t.max_anisotropy > 1) {
    const FV ratio = pmax / pmin;  // +∞ for pmin = 0; NaN for ∞/∞ and 0/0 (then unused)
    const IV below = ratio < static_cast<float>(t.max_anisotropy);
    const FV r = select(below, ratio, splat(1.0f));  // in [1, 16): converts exactly
    const IV whole = to_int(r);
    const IV ceil = whole - (to_float(whole) < r);  // std::ceil(ratio) of a positive ratio
    probes = select(pmax > 0.0f, select(below, ceil, splat_int(t.max_anisotropy)), probes);
  }
  const IV several = probes > 1;
  const FV lod = clamp_lod(t, log2_of(select(several, pmax / to_float(probes), pmax)));
  if (!any_lane(several)) return trilinear<kCh>(t, lod, u, v);
  // EXT_texture_filter_anisotropic's probes: lanes with one probe read (u, v) as the scalar
  // code does; the others the mean of theirs, summed in order, a probe past a lane's count
  // adding nothing.
  const FV mu = select(x_major, dudx, dudy), mv = select(x_major, dvdx, dvdy);
  const FV cu = coordinate(u), cv = coordinate(v);
  const FV n1 = to_float(probes + 1);
  int most = 1;
  for (int i = 0; i < kL; ++i) most = probes[i] > most ? probes[i] : most;
  RgbaV sum = {{FV{}, FV{}, FV{}, FV{}}};
  RgbaV single{};
  for (int i = 1; i <= most; ++i) {
    const FV w = static_cast<float>(i) / n1 - 0.5f;
    const RgbaV c = trilinear<kCh>(t, lod, select(several, cu + mu * w, u), select(several, cv + mv * w, v));
    if (i == 1) single = c;
    const IV taken = several & (splat_int(i) <= probes);
    for (int ch = 0; ch < 4; ++ch) sum.c[ch] = select(taken, sum.c[ch] + c.c[ch], sum.c[ch]);
  }
  const FV n = to_float(probes);
  RgbaV out;
  for (int ch = 0; ch < 4; ++ch) out.c[ch] = select(several, sum.c[ch] / n, single.c[ch]);
  return out;
}

}  // namespace texture_lanes

// Texture::sample_batch() for LaneTexture's textures and samplers, the channels in kCh.
template <unsigned kCh, bool kAniso>
void sample_lanes_of(const LaneTexture& t, int n, const Texture::Batch& b) {
  using namespace texture_lanes;
  for (int first = 0; first < n; first += kL) {
    const int m = n - first < kL ? n - first : kL;
    const float* in[6] = {b.u + first, b.v + first, b.dudx + first, b.dvdx + first, b.dudy + first, b.dvdy + first};
    float* out[4] = {b.r + first, b.g + first, b.b + first, b.a + first};
    // A partial group reads zeros beyond its m lanes and writes through a scratch copy, so
    // that the kernel's result is only ever stored whole: indexed lane by lane, GCC keeps
    // it in memory and copies it through the stack (zmm store-to-load chains on every call).
    alignas(64) float scratch_in[6][kL], scratch_out[4][kL];
    if (m < kL) {
      for (int k = 0; k < 6; ++k) {
        for (int i = 0; i < kL; ++i) scratch_in[k][i] = i < m ? in[k][i] : 0.0f;
        in[k] = scratch_in[k];
      }
    }
    FV lanes[6];
    for (int k = 0; k < 6; ++k) std::memcpy(&lanes[k], in[k], sizeof(FV));
    const RgbaV c = sample_v<kCh, kAniso>(t, lanes[0], lanes[1], lanes[2], lanes[3], lanes[4], lanes[5]);
    for (int ch = 0; ch < 4; ++ch) {
      if (!(kCh >> ch & 1)) continue;
      std::memcpy(m < kL ? scratch_out[ch] : out[ch], &c.c[ch], sizeof(FV));
      if (m < kL)
        for (int i = 0; i < m; ++i) out[ch][i] = scratch_out[ch][i];
    }
  }
}

// The channel sets the textured PBR shader asks for (colour, metallic-roughness's g and b,
// occlusion's r) have kernels of their own; any other set decodes all four.
// With AVX-512, isotropic samplers (max_anisotropy 1) have kernels without the probe loop
// (Zen 4, BM_TextureLookups: −4%; the AVX2 copy measured slower, it keeps one kernel).
template <bool kAniso>
void sample_lanes_by_channels(const LaneTexture& t, int n, const Texture::Batch& b) {
  constexpr unsigned kRgb = Texture::kRgb, kGb = Texture::kGreen | Texture::kBlue, kR = Texture::kRed;
  switch (b.channels & Texture::kRgba) {
    case kRgb: return sample_lanes_of<kRgb, kAniso>(t, n, b);
    case kGb: return sample_lanes_of<kGb, kAniso>(t, n, b);
    case kR: return sample_lanes_of<kR, kAniso>(t, n, b);
    default: return sample_lanes_of<Texture::kRgba, kAniso>(t, n, b);
  }
}
SOFTPBR_KERNEL void sample_lanes(const LaneTexture& t, int n, const Texture::Batch& b) {
#if SOFTPBR_TARGET_AVX512
  if (t.max_anisotropy == 1) return sample_lanes_by_channels<false>(t, n, b);
#endif
  sample_lanes_by_channels<true>(t, n, b);
}

#endif  // SOFTPBR_TARGET_AVX

}  // namespace softpbr::raster::detail::SOFTPBR_TARGET_NS

