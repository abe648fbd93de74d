// softpbr/simd/detail/lanes-inl.h — the lane types' operations, compiled per target.
//
// Included by softpbr/simd/simd.h through foreach_target.h once per target (no include
// guard; no header included here): simd::Lanes<N, SOFTPBR_ISA> and its operations are
// compiled for that target, so a kernel of that target inlines them as its own
// instructions (a lane operation compiled for baseline x86-64 and inlined into an AVX-512
// kernel came out split into narrower pieces, and compound compares into single lanes).
// Every operation is the same IEEE-754 single-precision operation per lane on every
// target and at every width (see simd.h).

namespace softpbr::simd {

template <int N>
struct Lanes<N, SOFTPBR_ISA> {
  static_assert(N == 4 || N == 8 || N == 16, "lane widths are 4, 8 and 16");
  using native = typename detail::Native<N>::f;
  using Mask = LaneMask<N, SOFTPBR_ISA>;
  native v;

  Lanes() = default;
  // Broadcast (implicit: uniforms mix with lanes). x − (+0) is x for every x, −0 included,
  // so compilers emit the bare broadcast; {} + x cost an add and made −0 into +0.
  Lanes(float x) : v(x - native{}) {}
  explicit Lanes(native n) : v(n) {}

  static Lanes load(const float* p) {
    Lanes r;
    __builtin_memcpy(&r.v, p, sizeof(native));
    return r;
  }
  void store(float* p) const { __builtin_memcpy(p, &v, sizeof(native)); }
  float operator[](int i) const { return v[i]; }

  Lanes operator-() const { return Lanes(-v); }
  Lanes& operator+=(Lanes b) { v += b.v; return *this; }
  Lanes& operator-=(Lanes b) { v -= b.v; return *this; }
  Lanes& operator*=(Lanes b) { v *= b.v; return *this; }
};

// The binary operators are free function templates, not friends defined in the class: GCC
// 12 compiles an in-class friend of a class template without the `#pragma GCC target` of
// the region it is written in, so a 16-lane compare inlined into an AVX-512 kernel came
// out as 16 scalar vcomiss (and a call where it could not inline). Each takes two lane
// vectors, or a lane vector and a float broadcast to every lane (what the friends' implicit
// conversion gave).
#define SOFTPBR_LANES_BINARY(op, Result)                                                \
  template <int N>                                                                      \
  inline Result<N, SOFTPBR_ISA> operator op(Lanes<N, SOFTPBR_ISA> a, Lanes<N, SOFTPBR_ISA> b) { \
    return Result<N, SOFTPBR_ISA>(a.v op b.v);                                          \
  }                                                                                     \
  template <int N>                                                                      \
  inline Result<N, SOFTPBR_ISA> operator op(Lanes<N, SOFTPBR_ISA> a, float s) {         \
    return Result<N, SOFTPBR_ISA>(a.v op Lanes<N, SOFTPBR_ISA>(s).v);                   \
  }                                                                                     \
  template <int N>                                                                      \
  inline Result<N, SOFTPBR_ISA> operator op(float s, Lanes<N, SOFTPBR_ISA> b) {         \
    return Result<N, SOFTPBR_ISA>(Lanes<N, SOFTPBR_ISA>(s).v op b.v);                   \
  }
SOFTPBR_LANES_BINARY(+, Lanes)
SOFTPBR_LANES_BINARY(-, Lanes)
SOFTPBR_LANES_BINARY(*, Lanes)
SOFTPBR_LANES_BINARY(/, Lanes)
SOFTPBR_LANES_BINARY(<, LaneMask)
SOFTPBR_LANES_BINARY(<=, LaneMask)
SOFTPBR_LANES_BINARY(>, LaneMask)
SOFTPBR_LANES_BINARY(>=, LaneMask)
#undef SOFTPBR_LANES_BINARY

template <int N>
struct LaneMask<N, SOFTPBR_ISA> {
  using native = typename detail::Native<N>::i;
  native m;  // all ones (−1) where true
  LaneMask() = default;
  explicit LaneMask(native n) : m(n) {}
  LaneMask operator!() const { return LaneMask(~m); }
  bool operator[](int i) const { return m[i] != 0; }
};

template <int N>
inline LaneMask<N, SOFTPBR_ISA> operator&(LaneMask<N, SOFTPBR_ISA> a, LaneMask<N, SOFTPBR_ISA> b) {
  return LaneMask<N, SOFTPBR_ISA>(a.m & b.m);
}
template <int N>
inline LaneMask<N, SOFTPBR_ISA> operator|(LaneMask<N, SOFTPBR_ISA> a, LaneMask<N, SOFTPBR_ISA> b) {
  return LaneMask<N, SOFTPBR_ISA>(a.m | b.m);
}

// Lane-wise choice: a vector conditional (a blend at any register width; a mask lane is
// all ones or all zeros).
template <int N>
inline Lanes<N, SOFTPBR_ISA> select(LaneMask<N, SOFTPBR_ISA> m, Lanes<N, SOFTPBR_ISA> a, Lanes<N, SOFTPBR_ISA> b) {
  return Lanes<N, SOFTPBR_ISA>(m.m ? a.v : b.v);
}

// min/max as comparisons, std::min's rule (b < a ? b : a), as for float: one vector
// conditional (vminps/vmaxps or a compare and a blend).
template <int N>
inline Lanes<N, SOFTPBR_ISA> min(Lanes<N, SOFTPBR_ISA> a, Lanes<N, SOFTPBR_ISA> b) {
  return Lanes<N, SOFTPBR_ISA>(b.v < a.v ? b.v : a.v);
}
template <int N>
inline Lanes<N, SOFTPBR_ISA> max(Lanes<N, SOFTPBR_ISA> a, Lanes<N, SOFTPBR_ISA> b) {
  return Lanes<N, SOFTPBR_ISA>(a.v < b.v ? b.v : a.v);
}

template <int N>
inline LaneMask<N, SOFTPBR_ISA> both(LaneMask<N, SOFTPBR_ISA> a, LaneMask<N, SOFTPBR_ISA> b) {
  return a & b;
}

// Whether any lane is set. With AVX, 4 and 8 lanes: vtestps of the mask's sign bits (one
// instruction and a branch on its flag; the sum below was seven dependent ones, about 6%
// of the fill kernel's time on Zen 3). Otherwise the mask feeds a blend and the lanes are
// summed as floats (a mask moved into integer registers costs more than the blend).
template <int N>
inline bool any(LaneMask<N, SOFTPBR_ISA> m) {
  using L = Lanes<N, SOFTPBR_ISA>;
#if SOFTPBR_TARGET_AVX
  if constexpr (N == 8) {
    const __m256 bits = reinterpret_cast<__m256>(m.m);
    return _mm256_testz_ps(bits, bits) == 0;
  } else if constexpr (N == 4) {
    const __m128 bits = reinterpret_cast<__m128>(m.m);
    return _mm_testz_ps(bits, bits) == 0;
  }
#endif
  const L ones = select(m, L(1.0f), L(0.0f));
  if constexpr (N == 4) {
    return ones.v[0] + ones.v[1] + ones.v[2] + ones.v[3] > 0.0f;
  } else {
    typename detail::Native<8>::f eight;
    if constexpr (N == 16) {
      eight = __builtin_shufflevector(ones.v, ones.v, 0, 1, 2, 3, 4, 5, 6, 7) +
              __builtin_shufflevector(ones.v, ones.v, 8, 9, 10, 11, 12, 13, 14, 15);
    } else {
      eight = ones.v;
    }
    const auto h = __builtin_shufflevector(eight, eight, 0, 1, 2, 3) + __builtin_shufflevector(eight, eight, 4, 5, 6, 7);
    return h[0] + h[1] + h[2] + h[3] > 0.0f;
  }
}

// Correctly rounded square root (IEEE-754 requires it of sqrtss/sqrtps alike).
template <int N>
inline Lanes<N, SOFTPBR_ISA> sqrt(Lanes<N, SOFTPBR_ISA> x) {
  using L = Lanes<N, SOFTPBR_ISA>;
#if SOFTPBR_TARGET_AVX512
  if constexpr (N == 16) {
    // The masked form with every lane selected: _mm512_sqrt_ps's undefined pass-through
    // operand trips GCC 12's -Wmaybe-uninitialized.
    const __m512 a = reinterpret_cast<__m512>(x.v);
    return L(reinterpret_cast<typename L::native>(_mm512_mask_sqrt_ps(a, static_cast<__mmask16>(0xffff), a)));
  }
#endif
#if SOFTPBR_TARGET_AVX
  if constexpr (N == 8) return L(reinterpret_cast<typename L::native>(_mm256_sqrt_ps(reinterpret_cast<__m256>(x.v))));
#endif
#if defined(__SSE2__)
  if constexpr (N == 4) {
    return L(reinterpret_cast<typename L::native>(_mm_sqrt_ps(reinterpret_cast<__m128>(x.v))));
  } else if constexpr (N == 8) {
    // Narrower registers than the vector: halves, split and joined in registers.
    using H = Lanes<4, SOFTPBR_ISA>;
    const H lo = sqrt(H(__builtin_shufflevector(x.v, x.v, 0, 1, 2, 3)));
    const H hi = sqrt(H(__builtin_shufflevector(x.v, x.v, 4, 5, 6, 7)));
    return L(__builtin_shufflevector(lo.v, hi.v, 0, 1, 2, 3, 4, 5, 6, 7));
  } else {
    using H = Lanes<8, SOFTPBR_ISA>;
    const H lo = sqrt(H(__builtin_shufflevector(x.v, x.v, 0, 1, 2, 3, 4, 5, 6, 7)));
    const H hi = sqrt(H(__builtin_shufflevector(x.v, x.v, 8, 9, 10, 11, 12, 13, 14, 15)));
    return L(__builtin_shufflevector(lo.v, hi.v, 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15));
  }
#else
  L out;
  for (int i = 0; i < N; ++i) out.v[i] = __builtin_sqrtf(x.v[i]);
  return out;
#endif
}

// Splits N records of four floats (e.g. RGBA pixels, p[4i] … p[4i + 3]) into four lane
// vectors: x[i] = p[4i], y[i] = p[4i + 1], … — a transpose in registers (lanes filled one
// float at a time and read back as a vector stall on store forwarding). Bits are moved,
// not computed on.
namespace detail {
// load_deinterleave4's transpose of q (N records of four floats, four records a vector).
template <int N>
inline void deinterleave4(const typename Native<16>::f* q, Lanes<N, SOFTPBR_ISA>& x, Lanes<N, SOFTPBR_ISA>& y,
                          Lanes<N, SOFTPBR_ISA>& z, Lanes<N, SOFTPBR_ISA>& w) {
  using L = Lanes<N, SOFTPBR_ISA>;
  if constexpr (N == 4) {
    x = L(__builtin_shufflevector(q[0], q[0], 0, 4, 8, 12));
    y = L(__builtin_shufflevector(q[0], q[0], 1, 5, 9, 13));
    z = L(__builtin_shufflevector(q[0], q[0], 2, 6, 10, 14));
    w = L(__builtin_shufflevector(q[0], q[0], 3, 7, 11, 15));
  } else if constexpr (N == 8) {
    x = L(__builtin_shufflevector(q[0], q[1], 0, 4, 8, 12, 16, 20, 24, 28));
    y = L(__builtin_shufflevector(q[0], q[1], 1, 5, 9, 13, 17, 21, 25, 29));
    z = L(__builtin_shufflevector(q[0], q[1], 2, 6, 10, 14, 18, 22, 26, 30));
    w = L(__builtin_shufflevector(q[0], q[1], 3, 7, 11, 15, 19, 23, 27, 31));
  } else {
    using H = Lanes<8, SOFTPBR_ISA>;
    H lo[4], hi[4];
    deinterleave4<8>(q, lo[0], lo[1], lo[2], lo[3]);
    deinterleave4<8>(q + 2, hi[0], hi[1], hi[2], hi[3]);
    L* out[4] = {&x, &y, &z, &w};
    for (int c = 0; c < 4; ++c)
      *out[c] = L(__builtin_shufflevector(lo[c].v, hi[c].v, 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15));
  }
}
}  // namespace detail

template <int N>
inline void load_deinterleave4(const float* p, Lanes<N, SOFTPBR_ISA>& x, Lanes<N, SOFTPBR_ISA>& y,
                               Lanes<N, SOFTPBR_ISA>& z, Lanes<N, SOFTPBR_ISA>& w) {
  typename detail::Native<16>::f q[N / 4];
  __builtin_memcpy(q, p, sizeof q);
  detail::deinterleave4<N>(q, x, y, z, w);
}

// The same from N records anywhere: record i (four floats at records[i]) into lane i — a
// texel of four floats per lane (bilinear lookups of float textures). Each record is one
// 16-byte load; the lanes are formed by the same transpose.
template <int N>
inline void load_deinterleave4(const float* const* records, Lanes<N, SOFTPBR_ISA>& x, Lanes<N, SOFTPBR_ISA>& y,
                               Lanes<N, SOFTPBR_ISA>& z, Lanes<N, SOFTPBR_ISA>& w) {
  using V4 = typename detail::Native<4>::f;
  typename detail::Native<16>::f q[N / 4];
  for (int k = 0; k < N / 4; ++k) {
    V4 r[4];
    for (int i = 0; i < 4; ++i) __builtin_memcpy(&r[i], records[4 * k + i], sizeof(V4));
    const auto ab = __builtin_shufflevector(r[0], r[1], 0, 1, 2, 3, 4, 5, 6, 7);
    const auto cd = __builtin_shufflevector(r[2], r[3], 0, 1, 2, 3, 4, 5, 6, 7);
    q[k] = __builtin_shufflevector(ab, cd, 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
  }
  detail::deinterleave4<N>(q, x, y, z, w);
}

// The inverse of load_deinterleave4: p[4i + 0..3] = x[i], y[i], z[i], w[i] for lane i —
// N pixels' RGBA as N records of four floats. A 4×4 transpose per four lanes by shuffles
// (unpcklps/unpckhps/shufps, and vperm2f128 to order 8 lanes' halves), so a packet's
// colours leave as whole 16-byte pixels instead of one float at a time.
template <int N>
inline void store_interleave4(Lanes<N, SOFTPBR_ISA> x, Lanes<N, SOFTPBR_ISA> y, Lanes<N, SOFTPBR_ISA> z,
                              Lanes<N, SOFTPBR_ISA> w, float* p) {
  if constexpr (N == 4) {
    const auto t0 = __builtin_shufflevector(x.v, y.v, 0, 4, 1, 5), t1 = __builtin_shufflevector(x.v, y.v, 2, 6, 3, 7);
    const auto t2 = __builtin_shufflevector(z.v, w.v, 0, 4, 1, 5), t3 = __builtin_shufflevector(z.v, w.v, 2, 6, 3, 7);
    const decltype(t0) o[4] = {__builtin_shufflevector(t0, t2, 0, 1, 4, 5), __builtin_shufflevector(t0, t2, 2, 3, 6, 7),
                               __builtin_shufflevector(t1, t3, 0, 1, 4, 5), __builtin_shufflevector(t1, t3, 2, 3, 6, 7)};
    __builtin_memcpy(p, o, sizeof o);
  } else if constexpr (N == 8) {
    // Within each 128-bit half, as for 4 lanes; then pixels i and i + 4 share a vector.
    const auto t0 = __builtin_shufflevector(x.v, y.v, 0, 8, 1, 9, 4, 12, 5, 13);
    const auto t1 = __builtin_shufflevector(x.v, y.v, 2, 10, 3, 11, 6, 14, 7, 15);
    const auto t2 = __builtin_shufflevector(z.v, w.v, 0, 8, 1, 9, 4, 12, 5, 13);
    const auto t3 = __builtin_shufflevector(z.v, w.v, 2, 10, 3, 11, 6, 14, 7, 15);
    const auto u0 = __builtin_shufflevector(t0, t2, 0, 1, 8, 9, 4, 5, 12, 13);    // pixels 0, 4
    const auto u1 = __builtin_shufflevector(t0, t2, 2, 3, 10, 11, 6, 7, 14, 15);  // 1, 5
    const auto u2 = __builtin_shufflevector(t1, t3, 0, 1, 8, 9, 4, 5, 12, 13);    // 2, 6
    const auto u3 = __builtin_shufflevector(t1, t3, 2, 3, 10, 11, 6, 7, 14, 15);  // 3, 7
    const decltype(u0) o[4] = {__builtin_shufflevector(u0, u1, 0, 1, 2, 3, 8, 9, 10, 11),
                               __builtin_shufflevector(u2, u3, 0, 1, 2, 3, 8, 9, 10, 11),
                               __builtin_shufflevector(u0, u1, 4, 5, 6, 7, 12, 13, 14, 15),
                               __builtin_shufflevector(u2, u3, 4, 5, 6, 7, 12, 13, 14, 15)};
    __builtin_memcpy(p, o, sizeof o);
  } else {
    using H = Lanes<8, SOFTPBR_ISA>;
    const auto lo = [](const Lanes<N, SOFTPBR_ISA>& a) {
      return H(__builtin_shufflevector(a.v, a.v, 0, 1, 2, 3, 4, 5, 6, 7));
    };
    const auto hi = [](const Lanes<N, SOFTPBR_ISA>& a) {
      return H(__builtin_shufflevector(a.v, a.v, 8, 9, 10, 11, 12, 13, 14, 15));
    };
    store_interleave4<8>(lo(x), lo(y), lo(z), lo(w), p);
    store_interleave4<8>(hi(x), hi(y), hi(z), hi(w), p + 32);
  }
}

// The bits of each lane (a reinterpretation, not a conversion).
template <int N>
inline UintLanes<N> bits_of(Lanes<N, SOFTPBR_ISA> x) {
  return (UintLanes<N>)x.v;
}
// Each lane's truncation toward zero stored to whole[0..N), and x minus it returned (the
// lanes must be in [0, 2^24)): the floor and fraction of a texel coordinate, as
// static_cast<int>(x) and x − float(that) give them. Only lane types cross the call, so a
// template compiled outside the target regions may use it (Clang refuses plain vectors
// there: their ABI depends on the target).
template <int N>
inline Lanes<N, SOFTPBR_ISA> split_whole(Lanes<N, SOFTPBR_ISA> x, std::uint32_t* whole) {
  using L = Lanes<N, SOFTPBR_ISA>;
  const auto i = __builtin_convertvector(x.v, typename detail::Native<N>::i);
  __builtin_memcpy(whole, &i, sizeof i);
  return L(x.v - __builtin_convertvector(i, typename L::native));
}

// Each lane truncated toward zero to an integer (the lanes must be in [0, 2^31)).
template <int N>
inline UintLanes<N> truncate_to_uint(Lanes<N, SOFTPBR_ISA> x) {
  return (UintLanes<N>)__builtin_convertvector(x.v, typename detail::Native<N>::i);
}

}  // namespace softpbr::simd

// What a kernel of this target names its lanes by: simd::SOFTPBR_TARGET_NS::Vec<N>, and
// the operations on plain vectors (simd::native_t) that take no lane type to overload on.
namespace softpbr::simd::SOFTPBR_TARGET_NS {

template <int N>
using Vec = Lanes<N, SOFTPBR_ISA>;
template <int N>
using Mask = LaneMask<N, SOFTPBR_ISA>;

// table[index[i]] for every lane: a plain loop, which compilers may turn into a gather
// instruction where the target has one.
template <int N>
inline UintLanes<N> gather(const std::uint32_t* table, UintLanes<N> index) {
  UintLanes<N> r;
  for (int i = 0; i < N; ++i) r[i] = table[index[i]];
  return r;
}

// Bit i set when lane i of four 64-bit integers is negative: their sign bits, as one
// vmovmskpd with AVX (two movmskpd with SSE2) instead of four extractions to general
// registers. Integer bits only: the result is the same on every target.
inline unsigned sign_bits(native_t<std::int64_t, 4> v) {
#if SOFTPBR_TARGET_AVX
  return static_cast<unsigned>(_mm256_movemask_pd(reinterpret_cast<__m256d>(v)));
#elif defined(__SSE2__)
  const native_t<std::int64_t, 2> lo = __builtin_shufflevector(v, v, 0, 1);
  const native_t<std::int64_t, 2> hi = __builtin_shufflevector(v, v, 2, 3);
  return static_cast<unsigned>(_mm_movemask_pd(reinterpret_cast<__m128d>(lo)) |
                               (_mm_movemask_pd(reinterpret_cast<__m128d>(hi)) << 2));
#else
  return static_cast<unsigned>((v[0] < 0) | ((v[1] < 0) << 1) | ((v[2] < 0) << 2) | ((v[3] < 0) << 3));
#endif
}
// Bit i set when lane i of eight 64-bit integers is negative (half of the MSAA quad
// stage's sample lanes): one vpmovq2m with AVX-512, else the four-lane form twice.
inline unsigned sign_bits8(native_t<std::int64_t, 8> v) {
#if SOFTPBR_TARGET_AVX512
  return static_cast<unsigned>(_mm512_movepi64_mask(reinterpret_cast<__m512i>(v)));
#else
  const native_t<std::int64_t, 4> lo = __builtin_shufflevector(v, v, 0, 1, 2, 3);
  const native_t<std::int64_t, 4> hi = __builtin_shufflevector(v, v, 4, 5, 6, 7);
  return sign_bits(lo) | (sign_bits(hi) << 4);
#endif
}
// N (4 or 8) 64-bit integers below 2^51 in magnitude as floats, each rounded once to
// nearest: the same bits as converting each integer directly (the rasterizer's edge values
// stay below 2^50, setup.h). x86 has no vector conversion from int64 before AVX-512DQ, so
// the direct form is scalar cvtsi2ss and their shuffles; here each integer is added to the
// bits of 2^52 + 2^51, whose double then holds 2^52 + 2^51 + v exactly, the constant is
// subtracted (exact), and one cvtpd2ps rounds the exact v to float.
template <int N>
inline native_t<float, N> to_float_below_2p51_n(native_t<std::int64_t, N> v) {
  using D = native_t<double, N>;
  constexpr std::int64_t kMagicBits = 0x4338000000000000;  // 2^52 + 2^51 as a double
  const native_t<std::int64_t, N> biased = v + kMagicBits;
  D d;
  __builtin_memcpy(&d, &biased, sizeof d);
  return __builtin_convertvector(d - 6755399441055744.0, native_t<float, N>);
}
inline native_t<float, 4> to_float_below_2p51(native_t<std::int64_t, 4> v) { return to_float_below_2p51_n<4>(v); }
// Bit i set when lane i of a 4-lane mask is set (movmskps where SSE has it).
inline unsigned mask_bits(LaneMask<4, SOFTPBR_ISA> m) {
#if defined(__SSE2__)
  return static_cast<unsigned>(_mm_movemask_ps(reinterpret_cast<__m128>(m.m)));
#else
  return static_cast<unsigned>((m.m[0] & 1) | (m.m[1] & 2) | (m.m[2] & 4) | (m.m[3] & 8));
#endif
}
// Bit i set when lane i of an 8- or 16-lane mask is set: vmovmskps (AVX) or vpmovd2m
// (AVX-512) where the target has one for the width, else movmskps per four lanes.
template <int N>
inline unsigned mask_bits(LaneMask<N, SOFTPBR_ISA> m) {
  static_assert(N == 8 || N == 16);
#if SOFTPBR_TARGET_AVX512
  if constexpr (N == 16) return static_cast<unsigned>(_mm512_movepi32_mask(reinterpret_cast<__m512i>(m.m)));
#endif
#if SOFTPBR_TARGET_AVX
  if constexpr (N == 8) return static_cast<unsigned>(_mm256_movemask_ps(reinterpret_cast<__m256>(m.m)));
#endif
  unsigned bits = 0;
  for (int q = 0; q < N / 4; ++q) {
    typename detail::Native<4>::i part;
    __builtin_memcpy(&part, reinterpret_cast<const char*>(&m.m) + q * sizeof part, sizeof part);
    bits |= mask_bits(LaneMask<4, SOFTPBR_ISA>(part)) << (4 * q);
  }
  return bits;
}
// The N-lane mask (4, 8 or 16) whose lane i is set when bit i of `bits` is.
template <int N = 4>
inline LaneMask<N, SOFTPBR_ISA> mask_from_bits(unsigned bits) {
  using I = typename detail::Native<N>::i;
  I lane_bit;
  for (int i = 0; i < N; ++i) lane_bit[i] = std::int32_t{1} << i;
  return LaneMask<N, SOFTPBR_ISA>(((I{} + static_cast<std::int32_t>(bits)) & lane_bit) != 0);
}

// The mask of lanes [0, n) of N (n in [0, N]).
template <int N>
inline LaneMask<N, SOFTPBR_ISA> first_lanes(int n) {
  using I = typename detail::Native<N>::i;
  I iota{};
  for (int i = 0; i < N; ++i) iota[i] = i;
  return LaneMask<N, SOFTPBR_ISA>(iota < (I{} + n));
}

// The lanes of x whose bit is set in `mask` (0 to 15), moved to the front in their order:
// lane k of the result is lane detail::kCompress4[mask][k] of x, for k < popcount(mask)
// (the others hold copies of x's lanes). A lane permutation, so the bits are kept: one
// vpermilps with AVX, a table lookup (tbl) where GCC has a variable shuffle for the
// target, else four loads by index.
inline native_t<float, 4> compress4(native_t<float, 4> x, unsigned mask) {
  const std::int32_t* const order = detail::kCompress4[mask & 0xFu];
#if SOFTPBR_TARGET_AVX
  return reinterpret_cast<native_t<float, 4>>(
      _mm_permutevar_ps(reinterpret_cast<__m128>(x), _mm_load_si128(reinterpret_cast<const __m128i*>(order))));
#elif defined(__GNUC__) && !defined(__clang__) && !defined(__SSE2__)
  native_t<std::int32_t, 4> index;
  __builtin_memcpy(&index, order, sizeof index);
  return __builtin_shuffle(x, index);
#else
  return native_t<float, 4>{x[order[0]], x[order[1]], x[order[2]], x[order[3]]};
#endif
}

// mask ? a : b per lane on the bits, for plain vectors of any element type (a mask lane
// is all ones or all zeros, as vector comparisons give).
template <class V, class M>
inline V bit_select(M mask, V a, V b) {
  return (V)(((M)a & mask) | ((M)b & ~mask));
}

}  // namespace softpbr::simd::SOFTPBR_TARGET_NS
