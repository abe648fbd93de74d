// softpbr/simd/simd.h — the lane types that packet shaders and kernels are written against.
//
// A packet shader is written once against a lane type F: `float` (one pixel) or
// simd::Vec<N> (N pixels, N = 4, 8 or 16, each lane an independent pixel). Every
// operation on lanes is the same IEEE-754 single-precision operation per lane as on
// float — +, −, ×, ÷, sqrt, comparisons, and min/max/select defined by the same
// comparison — so a lane computes bit for bit what the scalar code computes for that
// pixel, whatever the width and the instruction set (docs/design.md, "Determinism"). No
// FMA (the project compiles with -ffp-contract=off), no approximate reciprocals.
//
// Lanes<N, Isa> wraps a GCC/Clang vector extension, and its operations are compiled once
// per target (softpbr/simd/isa.h; detail/lanes-inl.h through foreach_target.h): a kernel
// compiled for AVX-512 shades with simd::Lanes<16, Isa::Avx512>, whose operations are
// AVX-512 code. simd::Vec<N> is Lanes<N, Isa::Baseline>, the build's own instruction set.
// This header (with lanes-inl.h and isa.h) is the only place with intrinsics.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>

#if defined(__SSE2__)
#include <immintrin.h>
#endif

#include "softpbr/simd/isa.h"

namespace softpbr::simd {

template <int N, Isa I>
struct Lanes;
template <int N, Isa I>
struct LaneMask;

namespace detail {
// GCC drops a vector_size that depends on a template parameter: spell out each width.
template <int N>
struct Native;
template <>
struct Native<4> {
  typedef float f __attribute__((vector_size(16)));
  typedef std::int32_t i __attribute__((vector_size(16)));
  typedef std::uint32_t u __attribute__((vector_size(16)));
  typedef float unaligned_f __attribute__((vector_size(16), aligned(1), may_alias));  // load_vector, store_vector
  typedef std::uint8_t bits;  // a bit a lane (store_masked's)
};
template <>
struct Native<8> {
  typedef float f __attribute__((vector_size(32)));
  typedef std::int32_t i __attribute__((vector_size(32)));
  typedef std::uint32_t u __attribute__((vector_size(32)));
  typedef float unaligned_f __attribute__((vector_size(32), aligned(1), may_alias));  // load_vector, store_vector
  typedef std::uint8_t bits;  // a bit a lane (store_masked's)
};
template <>
struct Native<16> {
  typedef float f __attribute__((vector_size(64)));
  typedef std::int32_t i __attribute__((vector_size(64)));
  typedef std::uint32_t u __attribute__((vector_size(64)));
  typedef float unaligned_f __attribute__((vector_size(64), aligned(1), may_alias));  // load_vector, store_vector
  typedef std::uint16_t bits;  // a bit a lane (store_masked's)
};
// compress4's table: for each 4-bit mask, the indices of its set bits in increasing order,
// the rest 0 (lane 0 again: any lane would do, the caller ignores them).
alignas(16) inline constexpr std::int32_t kCompress4[16][4] = {
    {0, 0, 0, 0}, {0, 0, 0, 0}, {1, 0, 0, 0}, {0, 1, 0, 0}, {2, 0, 0, 0}, {0, 2, 0, 0}, {1, 2, 0, 0}, {0, 1, 2, 0},
    {3, 0, 0, 0}, {0, 3, 0, 0}, {1, 3, 0, 0}, {0, 1, 3, 0}, {2, 3, 0, 0}, {0, 2, 3, 0}, {1, 2, 3, 0}, {0, 1, 2, 3}};
}  // namespace detail

// --- 32-bit unsigned integer lanes, for work on a float's bits (e.g. table lookups). ---
// Plain GCC/Clang vectors (& | ^ << >> + − and comparisons per lane, comparisons giving a
// signed all-ones/zero mask usable with `mask ? a : b`).
template <int N>
using UintLanes = typename detail::Native<N>::u;

// Plain vectors of N elements of T for kernels that compute on other element types (the
// vertex stage's doubles and 64-bit integers, the tile kernel's edge functions):
// native_t<T, N>. Operations on them are written in the kernel, which is compiled per
// target.
template <class T, int N>
struct NativeVector;
template <> struct NativeVector<float, 4> { typedef float type __attribute__((vector_size(16))); };
template <> struct NativeVector<std::int32_t, 4> { typedef std::int32_t type __attribute__((vector_size(16))); };
template <> struct NativeVector<std::int32_t, 8> { typedef std::int32_t type __attribute__((vector_size(32))); };
template <> struct NativeVector<std::int32_t, 16> { typedef std::int32_t type __attribute__((vector_size(64))); };
template <> struct NativeVector<double, 4> { typedef double type __attribute__((vector_size(32))); };
template <> struct NativeVector<std::int64_t, 2> { typedef std::int64_t type __attribute__((vector_size(16))); };
template <> struct NativeVector<std::int64_t, 4> { typedef std::int64_t type __attribute__((vector_size(32))); };
template <> struct NativeVector<std::int64_t, 8> { typedef std::int64_t type __attribute__((vector_size(64))); };
template <> struct NativeVector<double, 8> { typedef double type __attribute__((vector_size(64))); };
template <> struct NativeVector<float, 8> { typedef float type __attribute__((vector_size(32))); };
template <> struct NativeVector<float, 16> { typedef float type __attribute__((vector_size(64))); };
template <class T, int N>
using native_t = typename NativeVector<T, N>::type;

// 64 bytes of lanes of any type (bytes, 32-bit words, …), as x86's __m512i: 64-bit integers
// that may alias anything. What the byte operations (permute_bytes, lookup_bytes256,
// blend_bytes, the unpacks) and the word gathers work on; a kernel reads it as the lanes it
// holds by a vector cast (a reinterpretation).
typedef long long bits512_t __attribute__((vector_size(64), may_alias));


// --- The scalar forms of the lane operations, so code written against F works for float. ---

inline bool select(bool m, bool a, bool b) { return m ? a : b; }
inline float select(bool m, float a, float b) { return m ? a : b; }
// min/max as comparisons, identical for every lane type (std::min's rule: b < a ? b : a).
inline float min(float a, float b) { return b < a ? b : a; }
inline float max(float a, float b) { return a < b ? b : a; }
template <class F>
inline F clamp(F x, F lo, F hi) {
  return min(max(x, lo), hi);
}
// Logical and of two masks (for float: of two bools).
inline bool both(bool a, bool b) { return a && b; }
inline bool any(bool m) { return m; }
// Correctly rounded square root (IEEE-754 requires it of sqrtss/sqrtps alike).
inline float sqrt(float x) { return std::sqrt(x); }

}  // namespace softpbr::simd

// Lanes<N, I> and LaneMask<N, I> with their operations (select, min, max, both, any, sqrt,
// load_deinterleave4, bits_of, truncate_to_uint) for every target; the operations on plain
// vectors (simd::baseline, avx2, avx512: mask bits, gathers, table lookups, byte permutes,
// stores) once more for AVX-512 with VBMI (simd::avx512vbmi), whose byte permutes are
// VBMI's.
#define SOFTPBR_TARGET_FILE "softpbr/simd/detail/lanes-inl.h"
#define SOFTPBR_TARGET_ALSO_VBMI
#include "softpbr/simd/foreach_target.h"

namespace softpbr::simd {

// The lanes of the build's own instruction set: what code outside a dispatched kernel
// (tests, a user's own loops) names N pixels by.
template <int N>
using Vec = Lanes<N, Isa::Baseline>;
template <int N>
using Mask = LaneMask<N, Isa::Baseline>;

template <class F>
struct LaneCount {
  static constexpr int value = 1;
};
template <int N, Isa I>
struct LaneCount<Lanes<N, I>> {
  static constexpr int value = N;
};

// The widest lane count the build targets natively (chosen at compile time).
#if defined(__AVX512F__)
inline constexpr int kNativeWidth = 16;
#elif defined(__AVX2__)
inline constexpr int kNativeWidth = 8;
#else
inline constexpr int kNativeWidth = 4;
#endif

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
// Copies `bytes` bytes from src to dst, the 16-byte aligned part of dst with streaming
// stores where the target has them (the rest with plain stores). The bits are copied.
inline void stream_copy(void* dst, const void* src, std::size_t bytes) {
  char* d = static_cast<char*>(dst);
  const char* s = static_cast<const char*>(src);
#if defined(__SSE2__)
  std::size_t head = (16 - (reinterpret_cast<std::uintptr_t>(d) & 15)) & 15;
  if (head > bytes) head = bytes;
  std::memcpy(d, s, head);
  std::size_t i = head;
  for (; i + 16 <= bytes; i += 16)
    _mm_stream_ps(reinterpret_cast<float*>(d + i), _mm_loadu_ps(reinterpret_cast<const float*>(s + i)));
  std::memcpy(d + i, s + i, bytes - i);
#else
  std::memcpy(d, s, bytes);
#endif
}
inline void stream_fence() {
#if defined(__SSE2__)
  _mm_sfence();
#endif
}

// Tells the CPU that the thread is spinning on a flag another thread will set (x86's
// PAUSE, AArch64's YIELD): the spin uses less power and leaves its core to a sibling.
inline void spin_pause() {
#if defined(__SSE2__)
  _mm_pause();
#elif defined(__aarch64__)
  __asm__ __volatile__("yield" ::: "memory");
#endif
}

// The same pointer, which the compiler may no longer assume it knows: reads through it
// inside a loop are not hoisted out of it. For loop-invariant lanes kept in memory (a
// shader's per-draw uniforms): hoisted, each would want a register, and with more live
// lanes than registers GCC copies each from its home to a spill slot before the loop —
// two moves per value and loop — where a read inside the loop folds into the arithmetic as
// a memory operand. No effect on any value.
template <class T>
inline const T* in_memory(const T* p) {
#if defined(__GNUC__)
  __asm__("" : "+r"(p));
#endif
  return p;
}

// Three-vectors of lanes (or of floats) for shading code.
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
