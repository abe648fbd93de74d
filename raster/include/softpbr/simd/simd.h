// softpbr/simd/simd.h — the lane types that packet shaders are written against.
//
// A packet shader is written once against a lane type F: `float` (one pixel) or
// simd::Vec<N> (N pixels, N = 4, 8 or 16, each lane an independent pixel). Every
// operation on Vec<N> is the same IEEE-754 single-precision operation per lane as on
// float — +, −, ×, ÷, sqrt, comparisons, and min/max/select defined by the same
// comparison — so a lane computes bit for bit what the scalar code computes for that
// pixel, whatever the width (DESIGN.md §3). No FMA (the project compiles with
// -ffp-contract=off), no approximate reciprocals.
//
// Vec<N> wraps a GCC/Clang vector extension; the compiler maps it to SSE, AVX2 or
// AVX-512 registers as the target allows (wider vectors are split on narrower targets,
// with the same per-lane results). This header is the only place with intrinsics.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>

#if defined(__SSE2__)
#include <immintrin.h>
#endif

namespace softpbr::simd {

template <int N>
struct Mask;

namespace detail {
// GCC drops a vector_size that depends on a template parameter: spell out each width.
template <int N>
struct Native;
template <>
struct Native<4> {
  typedef float f __attribute__((vector_size(16)));
  typedef std::int32_t i __attribute__((vector_size(16)));
  typedef std::uint32_t u __attribute__((vector_size(16)));
};
template <>
struct Native<8> {
  typedef float f __attribute__((vector_size(32)));
  typedef std::int32_t i __attribute__((vector_size(32)));
  typedef std::uint32_t u __attribute__((vector_size(32)));
};
template <>
struct Native<16> {
  typedef float f __attribute__((vector_size(64)));
  typedef std::int32_t i __attribute__((vector_size(64)));
  typedef std::uint32_t u __attribute__((vector_size(64)));
};
}  // namespace detail

template <int N>
struct Vec {
  static_assert(N == 4 || N == 8 || N == 16, "lane widths are 4, 8 and 16");
  using native = typename detail::Native<N>::f;
  native v;

  Vec() = default;
  Vec(float x) : v(native{} + x) {}  // broadcast (implicit: uniforms mix with lanes)
  explicit Vec(native n) : v(n) {}

  static Vec load(const float* p) {
    Vec r;
    std::memcpy(&r.v, p, sizeof(native));
    return r;
  }
  void store(float* p) const { std::memcpy(p, &v, sizeof(native)); }
  float operator[](int i) const { return v[i]; }

  friend Vec operator+(Vec a, Vec b) { return Vec(a.v + b.v); }
  friend Vec operator-(Vec a, Vec b) { return Vec(a.v - b.v); }
  friend Vec operator*(Vec a, Vec b) { return Vec(a.v * b.v); }
  friend Vec operator/(Vec a, Vec b) { return Vec(a.v / b.v); }
  friend Vec operator-(Vec a) { return Vec(-a.v); }
  Vec& operator+=(Vec b) { v += b.v; return *this; }
  Vec& operator-=(Vec b) { v -= b.v; return *this; }
  Vec& operator*=(Vec b) { v *= b.v; return *this; }

  friend Mask<N> operator<(Vec a, Vec b) { return Mask<N>(a.v < b.v); }
  friend Mask<N> operator<=(Vec a, Vec b) { return Mask<N>(a.v <= b.v); }
  friend Mask<N> operator>(Vec a, Vec b) { return Mask<N>(a.v > b.v); }
  friend Mask<N> operator>=(Vec a, Vec b) { return Mask<N>(a.v >= b.v); }
};

template <int N>
struct Mask {
  using native = typename detail::Native<N>::i;
  native m;  // all ones (−1) where true
  Mask() = default;
  explicit Mask(native n) : m(n) {}
  friend Mask operator&(Mask a, Mask b) { return Mask(a.m & b.m); }
  friend Mask operator|(Mask a, Mask b) { return Mask(a.m | b.m); }
  friend Mask operator!(Mask a) { return Mask(~a.m); }
  bool operator[](int i) const { return m[i] != 0; }
};

// --- The operations shading code uses, for float and Vec<N> alike. ---

inline bool select(bool m, bool a, bool b) { return m ? a : b; }
inline float select(bool m, float a, float b) { return m ? a : b; }
// Lane-wise choice: a GCC/Clang vector conditional (a blend at any register width; a
// mask lane is all ones or all zeros). Written this way, a compare that reads a select's
// result stays a vector compare in a wide kernel compiled from this baseline code (a
// select through integer bit operations or memcpy gets split into single lanes there).
template <int N>
inline Vec<N> select(Mask<N> m, Vec<N> a, Vec<N> b) {
  return Vec<N>(m.m ? a.v : b.v);
}

// min/max as comparisons, identical for every lane type (std::min's rule: b < a ? b : a).
inline float min(float a, float b) { return b < a ? b : a; }
inline float max(float a, float b) { return a < b ? b : a; }
template <int N>
inline Vec<N> min(Vec<N> a, Vec<N> b) { return select(b < a, b, a); }
template <int N>
inline Vec<N> max(Vec<N> a, Vec<N> b) { return select(a < b, b, a); }
template <class F>
inline F clamp(F x, F lo, F hi) { return min(max(x, lo), hi); }

// Logical and of two masks (for float: of two bools).
inline bool both(bool a, bool b) { return a && b; }
template <int N>
inline Mask<N> both(Mask<N> a, Mask<N> b) { return a & b; }

inline bool any(bool m) { return m; }
// Whether any of eight non-negative lanes is above zero.
inline bool any_set(Vec<8> x) {
  const auto h = __builtin_shufflevector(x.v, x.v, 0, 1, 2, 3) + __builtin_shufflevector(x.v, x.v, 4, 5, 6, 7);
  return h[0] + h[1] + h[2] + h[3] > 0.0f;
}

// Whether any lane is set. The mask feeds a blend straight away and the sum is taken on
// floats: a mask used as data (or two masks combined with & |) is split into single lanes
// by GCC when the function is compiled for narrower registers than the vector, even once
// inlined into a wider kernel (see SOFTPBR_TARGET_AVX512); a blend is not.
template <int N>
inline bool any(Mask<N> m) {
  const Vec<N> ones = select(m, Vec<N>(1.0f), Vec<N>(0.0f));
  if constexpr (N == 16) {
    return any_set(Vec<8>(__builtin_shufflevector(ones.v, ones.v, 0, 1, 2, 3, 4, 5, 6, 7) +
                          __builtin_shufflevector(ones.v, ones.v, 8, 9, 10, 11, 12, 13, 14, 15)));
  } else if constexpr (N == 8) {
    return any_set(Vec<8>(ones.v));
  } else {
    return ones.v[0] + ones.v[1] + ones.v[2] + ones.v[3] > 0.0f;
  }
}

// Correctly rounded square root (IEEE-754 requires it of sqrtss/sqrtps alike).
inline float sqrt(float x) { return std::sqrt(x); }
template <int N>
inline Vec<N> sqrt(Vec<N> x) {
#if defined(__AVX512F__)
  if constexpr (N == 16) {
    __m512 r = _mm512_sqrt_ps(reinterpret_cast<__m512>(x.v));
    return Vec<N>(reinterpret_cast<typename Vec<N>::native>(r));
  }
#endif
#if defined(__AVX__)
  if constexpr (N == 8) {
    __m256 r = _mm256_sqrt_ps(reinterpret_cast<__m256>(x.v));
    return Vec<N>(reinterpret_cast<typename Vec<N>::native>(r));
  }
#endif
#if defined(__SSE2__)
  if constexpr (N == 4) {
    __m128 r = _mm_sqrt_ps(reinterpret_cast<__m128>(x.v));
    return Vec<N>(reinterpret_cast<typename Vec<N>::native>(r));
  } else if constexpr (N == 8) {
    // Narrower registers than the vector: halves, split and joined in registers (a trip
    // through memory would stall on store forwarding).
    const Vec<4> lo = sqrt(Vec<4>(__builtin_shufflevector(x.v, x.v, 0, 1, 2, 3)));
    const Vec<4> hi = sqrt(Vec<4>(__builtin_shufflevector(x.v, x.v, 4, 5, 6, 7)));
    return Vec<N>(__builtin_shufflevector(lo.v, hi.v, 0, 1, 2, 3, 4, 5, 6, 7));
  } else {
    const Vec<8> lo = sqrt(Vec<8>(__builtin_shufflevector(x.v, x.v, 0, 1, 2, 3, 4, 5, 6, 7)));
    const Vec<8> hi = sqrt(Vec<8>(__builtin_shufflevector(x.v, x.v, 8, 9, 10, 11, 12, 13, 14, 15)));
    return Vec<N>(__builtin_shufflevector(lo.v, hi.v, 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15));
  }
#else
  Vec<N> out;
  for (int i = 0; i < N; ++i) out.v[i] = std::sqrt(x.v[i]);
  return out;
#endif
}

// Splits N records of four floats (e.g. RGBA pixels, p[4i] … p[4i + 3]) into four lane
// vectors: x[i] = p[4i], y[i] = p[4i + 1], … (a transpose in registers: filling lanes one
// float at a time and reading them back as a vector stalls on store forwarding). Bits
// are moved, not computed on.
template <int N>
inline void load_deinterleave4(const float* p, Vec<N>& x, Vec<N>& y, Vec<N>& z, Vec<N>& w) {
  using V16 = typename detail::Native<16>::f;
  V16 q[N / 4];
  std::memcpy(q, p, sizeof q);
  if constexpr (N == 4) {
    x = Vec<N>(__builtin_shufflevector(q[0], q[0], 0, 4, 8, 12));
    y = Vec<N>(__builtin_shufflevector(q[0], q[0], 1, 5, 9, 13));
    z = Vec<N>(__builtin_shufflevector(q[0], q[0], 2, 6, 10, 14));
    w = Vec<N>(__builtin_shufflevector(q[0], q[0], 3, 7, 11, 15));
  } else if constexpr (N == 8) {
    x = Vec<N>(__builtin_shufflevector(q[0], q[1], 0, 4, 8, 12, 16, 20, 24, 28));
    y = Vec<N>(__builtin_shufflevector(q[0], q[1], 1, 5, 9, 13, 17, 21, 25, 29));
    z = Vec<N>(__builtin_shufflevector(q[0], q[1], 2, 6, 10, 14, 18, 22, 26, 30));
    w = Vec<N>(__builtin_shufflevector(q[0], q[1], 3, 7, 11, 15, 19, 23, 27, 31));
  } else {
    Vec<8> lo[4], hi[4];
    load_deinterleave4<8>(p, lo[0], lo[1], lo[2], lo[3]);
    load_deinterleave4<8>(p + 32, hi[0], hi[1], hi[2], hi[3]);
    Vec<N>* out[4] = {&x, &y, &z, &w};
    for (int c = 0; c < 4; ++c)
      *out[c] = Vec<N>(__builtin_shufflevector(lo[c].v, hi[c].v, 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15));
  }
}

// --- 32-bit unsigned integer lanes, for work on a float's bits (e.g. table lookups). ---
// Plain GCC/Clang vectors (& | ^ << >> + − and comparisons per lane, comparisons giving a
// signed all-ones/zero mask usable with `mask ? a : b`).
template <int N>
using UintLanes = typename detail::Native<N>::u;
// The bits of each lane (a reinterpretation, not a conversion).
template <int N>
inline UintLanes<N> bits_of(Vec<N> x) {
  return (UintLanes<N>)x.v;
}
// Each lane truncated toward zero to an integer (the lanes must be in [0, 2^31)).
template <int N>
inline UintLanes<N> truncate_to_uint(Vec<N> x) {
  return (UintLanes<N>)__builtin_convertvector(x.v, typename detail::Native<N>::i);
}
// table[index[i]] for every lane: a plain loop, which compilers may turn into a gather
// instruction where the target has one (no intrinsic: the same code on every target).
template <int N>
inline UintLanes<N> gather(const std::uint32_t* table, UintLanes<N> index) {
  UintLanes<N> r;
  for (int i = 0; i < N; ++i) r[i] = table[index[i]];
  return r;
}

// Whether kBytes bytes at a and b are the same (kBytes a multiple of 16): 16-byte
// vectors XORed and ORed together, no call (memcmp of a fixed size often is one).
template <std::size_t kBytes>
inline bool same_bytes(const void* a, const void* b) {
  static_assert(kBytes % 16 == 0, "whole 16-byte blocks");
  typedef std::uint64_t u64x2 __attribute__((vector_size(16)));
  u64x2 diff{};
  for (std::size_t i = 0; i < kBytes; i += 16) {
    u64x2 x, y;
    std::memcpy(&x, static_cast<const char*>(a) + i, 16);
    std::memcpy(&y, static_cast<const char*>(b) + i, 16);
    diff |= x ^ y;
  }
  return (diff[0] | diff[1]) == 0;
}

template <class F>
struct LaneCount {
  static constexpr int value = 1;
};
template <int N>
struct LaneCount<Vec<N>> {
  static constexpr int value = N;
};

// --- Runtime dispatch: kernels compiled for wider instruction sets than the build's. ---
//
// SOFTPBR_TARGET_AVX2 / SOFTPBR_TARGET_AVX512 mark a function compiled for AVX2 or
// AVX-512 whatever the build targets, with everything it calls inlined into it (flatten):
// the shading code inside is the very same source, its vector operations just map to
// wider registers. No FMA is enabled (and -ffp-contract=off forbids contraction anyway),
// no approximate reciprocal is used: the same IEEE operations, so the same bits. Such a
// function may only run when cpu_isa() says the CPU has the instruction set.
enum class Isa : std::uint8_t { Baseline, Avx2, Avx512 };

#if defined(__x86_64__) && defined(__GNUC__)
#define SOFTPBR_SIMD_DISPATCH 1
#define SOFTPBR_TARGET_AVX2 __attribute__((target("avx2,avx,popcnt"), flatten))
#define SOFTPBR_TARGET_AVX512 __attribute__((target("avx512f,avx512dq,avx512vl,avx512bw,avx2,avx,popcnt"), flatten))
// The widest instruction set of this CPU (and OS) that a dispatched kernel can use.
inline Isa cpu_isa() {
  static const Isa isa = [] {
    __builtin_cpu_init();
    if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq") &&
        __builtin_cpu_supports("avx512vl") && __builtin_cpu_supports("avx512bw"))
      return Isa::Avx512;
    if (__builtin_cpu_supports("avx2")) return Isa::Avx2;
    return Isa::Baseline;
  }();
  return isa;
}
#else
#define SOFTPBR_SIMD_DISPATCH 0
inline Isa cpu_isa() { return Isa::Baseline; }
#endif

// Writes the four floats `pattern` n times from dst (n × 16 bytes) with streaming
// (non-temporal) stores where the target has them: memory written that nobody reads soon
// stays out of the cache. Call stream_fence() before other threads read it.
inline void stream_fill4(float* dst, const float pattern[4], std::size_t n) {
#if defined(__SSE2__)
  const __m128 p = _mm_loadu_ps(pattern);
  std::size_t i = 0;
  for (; i < n && (reinterpret_cast<std::uintptr_t>(dst + 4 * i) & 15) != 0; ++i) _mm_storeu_ps(dst + 4 * i, p);
  for (; i < n; ++i) _mm_stream_ps(dst + 4 * i, p);
#else
  for (std::size_t i = 0; i < n; ++i) std::memcpy(dst + 4 * i, pattern, 4 * sizeof(float));
#endif
}
inline void stream_fence() {
#if defined(__SSE2__)
  _mm_sfence();
#endif
}

// The widest lane count the compiler targets natively (chosen at compile time).
#if defined(__AVX512F__)
inline constexpr int kNativeWidth = 16;
#elif defined(__AVX2__)
inline constexpr int kNativeWidth = 8;
#else
inline constexpr int kNativeWidth = 4;
#endif

// Three and four lanes-of-F vectors for shading code.
template <class F>
struct Vec3 {
  F x, y, z;
  Vec3() = default;
  Vec3(F a, F b, F c) : x(a), y(b), z(c) {}
  explicit Vec3(F s) : x(s), y(s), z(s) {}
  friend Vec3 operator+(const Vec3& a, const Vec3& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
  friend Vec3 operator-(const Vec3& a, const Vec3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
  friend Vec3 operator*(const Vec3& a, const Vec3& b) { return {a.x * b.x, a.y * b.y, a.z * b.z}; }
  friend Vec3 operator*(const Vec3& a, F s) { return {a.x * s, a.y * s, a.z * s}; }
  friend Vec3 operator/(const Vec3& a, F s) { return {a.x / s, a.y / s, a.z / s}; }
  friend Vec3 operator-(const Vec3& a) { return {-a.x, -a.y, -a.z}; }
  Vec3& operator+=(const Vec3& b) {
    x += b.x;
    y += b.y;
    z += b.z;
    return *this;
  }
};

template <class F>
inline F dot(const Vec3<F>& a, const Vec3<F>& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}

template <class M, class F>
inline Vec3<F> select(M m, const Vec3<F>& a, const Vec3<F>& b) {
  return {select(m, a.x, b.x), select(m, a.y, b.y), select(m, a.z, b.z)};
}

}  // namespace softpbr::simd
