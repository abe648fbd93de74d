// softpbr/simd/detail/lanes-inl.h — the lane types' operations, compiled per target.
//
// Included by softpbr/simd/simd.h through foreach_target.h once per target (no include
// guard; no header included here): simd::Lanes<N, SOFTPBR_ISA> and its operations are
// compiled for that target, so a kernel of that target inlines them as its own
// instructions (a lane operation compiled for baseline x86-64 and inlined into an AVX-512
// kernel came out split into narrower pieces, and compound compares into single lanes).
// Every operation is the same IEEE-754 single-precision operation per lane on every
// target and at every width (see simd.h). The AVX-512 VBMI copy (SOFTPBR_TARGET_VBMI,
// foreach_target.h) compiles only the operations on plain vectors, in namespace
// simd::avx512vbmi: its lane types are AVX-512's.

#if !SOFTPBR_TARGET_VBMI
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
#endif  // !SOFTPBR_TARGET_VBMI

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
// Bit i set when lane i of a mask is set (4, 8 or 16 lanes of 32 bits, each all ones or
// zeros, as vector comparisons give; a plain vector or a LaneMask): movmskps (SSE),
// vmovmskps (AVX, 8 lanes), vpmovd2m (AVX-512, 16 lanes), else movmskps per four lanes.
template <int N>
inline unsigned mask_bits_of(typename detail::Native<N>::i m) {
#if SOFTPBR_TARGET_AVX512
  if constexpr (N == 16) return static_cast<unsigned>(_mm512_movepi32_mask(reinterpret_cast<__m512i>(m)));
#endif
#if SOFTPBR_TARGET_AVX
  if constexpr (N == 8) return static_cast<unsigned>(_mm256_movemask_ps(reinterpret_cast<__m256>(m)));
#endif
  if constexpr (N == 4) {
#if defined(__SSE2__)
    return static_cast<unsigned>(_mm_movemask_ps(reinterpret_cast<__m128>(m)));
#else
    return static_cast<unsigned>((m[0] & 1) | (m[1] & 2) | (m[2] & 4) | (m[3] & 8));
#endif
  } else {
    unsigned bits = 0;
    for (int q = 0; q < N / 4; ++q) {
      typename detail::Native<4>::i part;
      __builtin_memcpy(&part, reinterpret_cast<const char*>(&m) + q * sizeof part, sizeof part);
      bits |= mask_bits_of<4>(part) << (4 * q);
    }
    return bits;
  }
}
inline unsigned mask_bits(native_t<std::int32_t, 4> m) { return mask_bits_of<4>(m); }
inline unsigned mask_bits(native_t<std::int32_t, 8> m) { return mask_bits_of<8>(m); }
inline unsigned mask_bits(native_t<std::int32_t, 16> m) { return mask_bits_of<16>(m); }
template <int N>
inline unsigned mask_bits(LaneMask<N, SOFTPBR_ISA> m) {
  return mask_bits_of<N>(m.m);
}
// Whether any lane, or every lane, of a mask is set (a plain vector or a LaneMask, as
// mask_bits): its bits tested in a general register. (simd::any tests a LaneMask in vector
// registers: vtestps with AVX.)
template <class M>
inline bool any_lane(M m) {
  return mask_bits(m) != 0;
}
template <class M>
inline bool all_lanes(M m) {
  return mask_bits(m) == (1u << (sizeof(M) / 4)) - 1;
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

// --- Stores. ---

// v stored at p (any alignment) as one store of v's width where the target has registers
// that wide (a 64-byte vmovups with AVX-512): GCC copies a 64-byte vector by memcpy, as
// Lanes::store does, in pieces of its preferred width (two 32-byte stores on Zen 4). No
// intrinsic: a store through an unaligned vector type, which narrower targets split.
template <int N>
inline void store_vector(float* p, typename detail::Native<N>::f v) {
  *reinterpret_cast<typename detail::Native<N>::unaligned_f*>(p) = v;
}

// N floats loaded from p (any alignment), through a type that may alias anything (as
// _mm_loadu_ps: the compiler assumes p may point at any object, where Lanes::load's
// memcpy lets it tell floats from other types; the tile kernel's code was scheduled on
// that).
template <int N>
inline typename detail::Native<N>::f load_vector(const float* p) {
  return *reinterpret_cast<const typename detail::Native<N>::unaligned_f*>(p);
}

// The lanes of v (4, 8 or 16 floats) whose bit is set in `bits` (bit i: lane i; 8 bits for
// 4 and 8 lanes, 16 for 16, as AVX-512's mask registers: the caller's value is narrowed
// where it is computed, as a cast to __mmask8 there was) stored to p[i]; the others neither
// read nor written. AVX-512: one masked vmovups; elsewhere one store a lane.
template <int N>
inline void store_masked(float* p, typename detail::Native<N>::bits bits, typename detail::Native<N>::f v) {
#if SOFTPBR_TARGET_AVX512
  if constexpr (N == 4) {
    _mm_mask_storeu_ps(p, bits, reinterpret_cast<__m128>(v));
  } else if constexpr (N == 8) {
    _mm256_mask_storeu_ps(p, bits, reinterpret_cast<__m256>(v));
  } else {
    _mm512_mask_storeu_ps(p, bits, reinterpret_cast<__m512>(v));
  }
#else
  for (int i = 0; i < N; ++i)
    if (bits >> i & 1u) p[i] = v[i];
#endif
}

// --- Gathers and table lookups on 16 lanes of 32 bits (e.g. RGBA8 texels). ---

#if SOFTPBR_TARGET_AVX512
namespace gather_detail {
// The lanes' indices stored to `at`, to be read back by plain loads: the empty asm keeps
// GCC from taking each out of the vector register instead (vpextrd, two micro-ops on
// Zen 4, against one for a load).
inline void store_indices(std::int32_t (&at)[16], native_t<std::int32_t, 16> index) {
  __builtin_memcpy(at, &index, sizeof at);
  asm("" : "+m"(at));
}
}  // namespace gather_detail
#endif

// Lane i: the 32-bit word at words + 4 · index[i] (index[i] ≥ 0; any alignment), one load
// a lane. AVX-512: the loads put together by inserts (vmovd, vpinsrd, then the 16-byte
// pieces joined): 16 dword stores and one 64-byte load would wait for the stores to
// retire, and vpgatherdd measured 5% slower in the texture kernel (fill8x_tex, Zen 4).
// `words` is a reference, read where each word is loaded, after the indices are stored, as
// the texture kernel's own code read it: a pointer argument, read before the store, changed
// that kernel's schedule, registers and spill slots (its disassembly compared).
inline bits512_t gather_words(const std::uint8_t* const& words, native_t<std::int32_t, 16> index) {
#if SOFTPBR_TARGET_AVX512
  alignas(64) std::int32_t at[16];
  gather_detail::store_indices(at, index);
  auto word = [&](int i) {
    std::int32_t x;
    __builtin_memcpy(&x, words + static_cast<std::size_t>(at[i]) * 4, 4);
    return x;
  };
  __m128i q[4];
  for (int j = 0; j < 4; ++j) {
    q[j] = _mm_cvtsi32_si128(word(4 * j));
    q[j] = _mm_insert_epi32(q[j], word(4 * j + 1), 1);
    q[j] = _mm_insert_epi32(q[j], word(4 * j + 2), 2);
    q[j] = _mm_insert_epi32(q[j], word(4 * j + 3), 3);
  }
  // Concatenated by vector shuffles (GCC 12's _mm512_inserti64x4 warns of its undefined
  // pass-through operand).
  typedef std::int32_t I4 __attribute__((vector_size(16)));
  typedef std::int32_t I8 __attribute__((vector_size(32)));
  const I8 lo = __builtin_shufflevector((I4)q[0], (I4)q[1], 0, 1, 2, 3, 4, 5, 6, 7);
  const I8 hi = __builtin_shufflevector((I4)q[2], (I4)q[3], 0, 1, 2, 3, 4, 5, 6, 7);
  return (bits512_t)__builtin_shufflevector(lo, hi, 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
#else
  native_t<std::int32_t, 16> r;
  for (int i = 0; i < 16; ++i) {
    std::int32_t x;
    __builtin_memcpy(&x, words + static_cast<std::size_t>(index[i]) * 4, 4);
    r[i] = x;
  }
  return (bits512_t)r;
#endif
}

// Lane i of `first` and `second` (32-bit words): the words at words + 4 · index[i] and the
// one after it, by one 8-byte load a lane (half the loads of two gather_words). AVX-512:
// the pairs put together by inserts (vmovq, vpinsrq), then split into the two vectors by
// two dword permutes (vpermt2d). `words` as for gather_words.
inline void gather_word_pairs(const std::uint8_t* const& words, native_t<std::int32_t, 16> index, bits512_t& first,
                              bits512_t& second) {
#if SOFTPBR_TARGET_AVX512
  alignas(64) std::int32_t at[16];
  gather_detail::store_indices(at, index);
  auto pair = [&](int i) {
    long long x;
    __builtin_memcpy(&x, words + static_cast<std::size_t>(at[i]) * 4, 8);
    return x;
  };
  __m128i q[8];
  for (int j = 0; j < 8; ++j) q[j] = _mm_insert_epi64(_mm_cvtsi64_si128(pair(2 * j)), pair(2 * j + 1), 1);
  typedef long long L2 __attribute__((vector_size(16)));
  typedef long long L4 __attribute__((vector_size(32)));
  const L4 a0 = __builtin_shufflevector((L2)q[0], (L2)q[1], 0, 1, 2, 3);
  const L4 a1 = __builtin_shufflevector((L2)q[2], (L2)q[3], 0, 1, 2, 3);
  const L4 b0 = __builtin_shufflevector((L2)q[4], (L2)q[5], 0, 1, 2, 3);
  const L4 b1 = __builtin_shufflevector((L2)q[6], (L2)q[7], 0, 1, 2, 3);
  const __m512i a = (__m512i)__builtin_shufflevector(a0, a1, 0, 1, 2, 3, 4, 5, 6, 7);  // lanes 0–7's pairs
  const __m512i b = (__m512i)__builtin_shufflevector(b0, b1, 0, 1, 2, 3, 4, 5, 6, 7);  // lanes 8–15's
  const __m512i even = _mm512_set_epi32(30, 28, 26, 24, 22, 20, 18, 16, 14, 12, 10, 8, 6, 4, 2, 0);
  first = _mm512_permutex2var_epi32(a, even, b);
  second = _mm512_permutex2var_epi32(a, _mm512_add_epi32(even, _mm512_set1_epi32(1)), b);
#else
  native_t<std::int32_t, 16> f, s;
  for (int i = 0; i < 16; ++i) {
    std::int32_t x[2];
    __builtin_memcpy(x, words + static_cast<std::size_t>(index[i]) * 4, 8);
    f[i] = x[0];
    s[i] = x[1];
  }
  first = (bits512_t)f;
  second = (bits512_t)s;
#endif
}

// table[code[i] & 255] for each of 16 lanes: a table of 256 floats. AVX-512: held in 16
// registers, vpermt2ps reads 32 entries by the code's bits 0–4 and three selects on bits 5,
// 6, 7 pick among the eight 32-entry quarters (no loads a lane); elsewhere one load a lane.
// Pure data movement: the table's floats, bit for bit.
inline native_t<float, 16> lookup_floats256(const float* table, native_t<std::int32_t, 16> code) {
#if SOFTPBR_TARGET_AVX512
  const __m512i k = (__m512i)code;
  __m512 t[8];
  for (int j = 0; j < 8; ++j)
    t[j] = _mm512_permutex2var_ps(_mm512_loadu_ps(table + 32 * j), k, _mm512_loadu_ps(table + 32 * j + 16));
  const __mmask16 b5 = _mm512_test_epi32_mask(k, _mm512_set1_epi32(32));
  const __mmask16 b6 = _mm512_test_epi32_mask(k, _mm512_set1_epi32(64));
  const __mmask16 b7 = _mm512_test_epi32_mask(k, _mm512_set1_epi32(128));
  const __m512 u0 = _mm512_mask_blend_ps(b5, t[0], t[1]), u1 = _mm512_mask_blend_ps(b5, t[2], t[3]);
  const __m512 u2 = _mm512_mask_blend_ps(b5, t[4], t[5]), u3 = _mm512_mask_blend_ps(b5, t[6], t[7]);
  const __m512 v0 = _mm512_mask_blend_ps(b6, u0, u1), v1 = _mm512_mask_blend_ps(b6, u2, u3);
  return (native_t<float, 16>)_mm512_mask_blend_ps(b7, v0, v1);
#else
  native_t<float, 16> r;
  for (int i = 0; i < 16; ++i) r[i] = table[code[i] & 255];
  return r;
#endif
}

// --- Bytes: 64 in a bits512_t. ---

// The 64 bytes at p (any alignment), as a bits512_t.
inline bits512_t load_bits512(const void* p) {
  typedef long long Unaligned __attribute__((vector_size(64), may_alias, aligned(1)));
  return *static_cast<const Unaligned*>(p);
}

// Byte i: byte index[i] & 127 of the 128 bytes a then b (a two-table byte permute:
// vpermt2b with AVX-512 VBMI; elsewhere one byte at a time).
inline bits512_t permute_bytes(bits512_t a, bits512_t index, bits512_t b) {
#if SOFTPBR_TARGET_VBMI
  return _mm512_permutex2var_epi8(a, index, b);
#else
  typedef std::uint8_t B __attribute__((vector_size(64)));
  const B x = (B)a, k = (B)index, y = (B)b;
  B r;
  for (int i = 0; i < 64; ++i) r[i] = k[i] & 64 ? y[k[i] & 63] : x[k[i] & 63];
  return (bits512_t)r;
#endif
}

// Byte i: table[index[i]], a table of 256 bytes (any alignment). With VBMI: the table in
// four registers, two byte permutes (by bits 0–6) and a select on bit 7 (vpmovb2m,
// vpblendmb); elsewhere one byte at a time.
inline bits512_t lookup_bytes256(const std::uint8_t* table, bits512_t index) {
#if SOFTPBR_TARGET_VBMI
  const __mmask64 high = _mm512_movepi8_mask(index);
  const __m512i lo = _mm512_permutex2var_epi8(_mm512_loadu_si512(table), index, _mm512_loadu_si512(table + 64));
  const __m512i hi = _mm512_permutex2var_epi8(_mm512_loadu_si512(table + 128), index, _mm512_loadu_si512(table + 192));
  return _mm512_mask_blend_epi8(high, lo, hi);
#else
  typedef std::uint8_t B __attribute__((vector_size(64)));
  const B k = (B)index;
  B r;
  for (int i = 0; i < 64; ++i) r[i] = table[k[i]];
  return (bits512_t)r;
#endif
}

// Byte i: b[i] where bit i of `bits` is set, else a[i] (vpblendmb with AVX-512).
inline bits512_t blend_bytes(std::uint64_t bits, bits512_t a, bits512_t b) {
#if SOFTPBR_TARGET_AVX512
  return _mm512_mask_blend_epi8(static_cast<__mmask64>(bits), a, b);
#else
  typedef std::uint8_t B __attribute__((vector_size(64)));
  const B x = (B)a, y = (B)b;
  B r;
  for (int i = 0; i < 64; ++i) r[i] = bits >> i & 1u ? y[i] : x[i];
  return (bits512_t)r;
#endif
}

// x86's unpacks, within each 16-byte block of a and b: the units (kUnit = 1 or 2 bytes) of
// the block's low (kHigh false) or high half of a and b, alternately: a₀ b₀ a₁ b₁ …
// (vpunpcklbw, vpunpckhbw, vpunpcklwd, vpunpckhwd with AVX-512; elsewhere byte by byte).
// unpack_lo8, unpack_hi8 (bytes), unpack_lo16, unpack_hi16 (16-bit units) name them.
template <int kUnit, bool kHigh>
inline bits512_t unpack(bits512_t a, bits512_t b) {
  static_assert(kUnit == 1 || kUnit == 2, "units of 1 or 2 bytes");
#if SOFTPBR_TARGET_AVX512
  if constexpr (kUnit == 1) {
    return kHigh ? _mm512_unpackhi_epi8(a, b) : _mm512_unpacklo_epi8(a, b);
  } else {
    return kHigh ? _mm512_unpackhi_epi16(a, b) : _mm512_unpacklo_epi16(a, b);
  }
#else
  typedef std::uint8_t B __attribute__((vector_size(64)));
  const B x = (B)a, y = (B)b;
  B r;
  for (int block = 0; block < 64; block += 16)
    for (int u = 0; u < 8 / kUnit; ++u)
      for (int e = 0; e < kUnit; ++e) {
        const int from = block + (kHigh ? 8 : 0) + kUnit * u + e;
        r[block + 2 * kUnit * u + e] = x[from];
        r[block + 2 * kUnit * u + kUnit + e] = y[from];
      }
  return (bits512_t)r;
#endif
}
inline bits512_t unpack_lo8(bits512_t a, bits512_t b) { return unpack<1, false>(a, b); }
inline bits512_t unpack_hi8(bits512_t a, bits512_t b) { return unpack<1, true>(a, b); }
inline bits512_t unpack_lo16(bits512_t a, bits512_t b) { return unpack<2, false>(a, b); }
inline bits512_t unpack_hi16(bits512_t a, bits512_t b) { return unpack<2, true>(a, b); }

}  // namespace softpbr::simd::SOFTPBR_TARGET_NS
