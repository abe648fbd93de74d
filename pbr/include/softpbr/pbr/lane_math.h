// softpbr/pbr/lane_math.h — log2, exp2, exp and pow per lane, from basic operations only.
//
// The sheen layer's distribution and visibility (brdf.h) raise numbers to per-pixel
// powers. libm's powf differs between libraries in the last bits, and dmath works in double
// on one value at a time; these work on any lane type F (float or simd::Lanes) with the
// same IEEE operations per lane in a fixed order (+, −, ×, ÷, comparisons and selects: no
// FMA, no table, no bit tricks), so every lane width, compiler and CPU gives the same bits.
// Each has a double overload that calls dmath, so a term written once against F also
// serves as its own double-precision oracle (tests/test_layers.cpp measures the error:
// exp2 within 8·10⁻⁸ relative, log2 within one float ulp of its result (3.8·10⁻⁶ at
// |log2 x| near 100), pow within 10⁻⁵ relative: the rounding of y · log2 x, whose product
// reaches 3000 for the sheen's exponents, dominates).
#pragma once

#include <cmath>

#include "softpbr/dmath/dmath.h"
#include "softpbr/simd/simd.h"

namespace softpbr::simd {
// The scalar select of simd.h for double, so that terms written against F build in double.
inline double select(bool m, double a, double b) { return m ? a : b; }
inline double max(double a, double b) { return a < b ? b : a; }
inline double min(double a, double b) { return b < a ? b : a; }
inline double sqrt(double x) { return std::sqrt(x); }  // correctly rounded, as IEEE requires
}  // namespace softpbr::simd

namespace softpbr::pbr {

// log2(x) for x > 0. x is first raised to 2⁻¹²⁶ (the smallest normal float; NaN reads as
// that too), then brought into [1, 2) by multiplying by powers of two (exact), counting
// them in e: seven steps of 2^±64 … 2^±1, a binary search over the exponent. With m in
// (√½, √2], ln m = 2 atanh(s) = 2 (s + s³/3 + s⁵/5 + s⁷/7 + s⁹/9), s = (m − 1)/(m + 1),
// |s| ≤ 0.172: the first omitted term is below 2·10⁻⁹ of the sum.
template <class F>
inline F log2_lanes(F x) {
  const F one(1.0f);
  x = simd::max(F(0x1p-126f), x);  // max(a, b) is b < a ? … : keeps the first for NaN
  F e(0.0f);
  constexpr float kSteps[7] = {64.0f, 32.0f, 16.0f, 8.0f, 4.0f, 2.0f, 1.0f};
  constexpr float kUp[7] = {0x1p64f, 0x1p32f, 0x1p16f, 0x1p8f, 0x1p4f, 0x1p2f, 0x1p1f};
  constexpr float kDown[7] = {0x1p-64f, 0x1p-32f, 0x1p-16f, 0x1p-8f, 0x1p-4f, 0x1p-2f, 0x1p-1f};
  // Down to below 2 (before step k, x < 2^(2k); after it, x < 2^k) …
  for (int i = 0; i < 7; ++i) {
    const auto big = x >= F(kUp[i]);
    x = simd::select(big, x * F(kDown[i]), x);
    e = simd::select(big, e + F(kSteps[i]), e);
  }
  // … and up to at least 1 (before step k, x ≥ 2^(1 − 2k); after it, x ≥ 2^(1 − k)).
  for (int i = 0; i < 7; ++i) {
    const auto small = x < F(kDown[i] + kDown[i]);
    x = simd::select(small, x * F(kUp[i]), x);
    e = simd::select(small, e - F(kSteps[i]), e);
  }
  const auto high = x > F(1.41421356237309504880f);
  x = simd::select(high, x * F(0.5f), x);
  e = simd::select(high, e + one, e);
  const F s = (x - one) / (x + one);
  const F z = s * s;
  const F series = one + z * (F(1.0f / 3.0f) + z * (F(0.2f) + z * (F(1.0f / 7.0f) + z * F(1.0f / 9.0f))));
  const F ln_m = (s + s) * series;
  return e + ln_m * F(1.44269504088896340736f);
}

// 2^y, y clamped to [−125, 126] (NaN reads as −125): the result stays a normal float.
// y = n + f with n = round(y) (adding and subtracting 1.5 · 2²³, exact for |y| < 2²²) and
// |f| ≤ 1/2; 2^f = e^(f ln 2) by its Taylor series to the 7th power (|f ln 2| ≤ 0.347: the
// first omitted term is below 6·10⁻⁹), then times 2^n in seven exact steps.
template <class F>
inline F exp2_lanes(F y) {
  const F one(1.0f);
  y = simd::min(F(126.0f), simd::max(F(-125.0f), y));
  const F magic(12582912.0f);  // 1.5 · 2²³
  const F n = (y + magic) - magic;
  const F x = (y - n) * F(0.693147180559945309417f);
  F p = one + x * (one + x * (F(0.5f) + x * (F(1.0f / 6.0f) + x * (F(1.0f / 24.0f) +
                                        x * (F(1.0f / 120.0f) + x * (F(1.0f / 720.0f) + x * F(1.0f / 5040.0f)))))));
  const auto negative = n < F(0.0f);
  F a = simd::select(negative, F(0.0f) - n, n);
  constexpr float kSteps[7] = {64.0f, 32.0f, 16.0f, 8.0f, 4.0f, 2.0f, 1.0f};
  constexpr float kUp[7] = {0x1p64f, 0x1p32f, 0x1p16f, 0x1p8f, 0x1p4f, 0x1p2f, 0x1p1f};
  constexpr float kDown[7] = {0x1p-64f, 0x1p-32f, 0x1p-16f, 0x1p-8f, 0x1p-4f, 0x1p-2f, 0x1p-1f};
  for (int i = 0; i < 7; ++i) {
    const auto take = a >= F(kSteps[i]);
    p = simd::select(take, p * simd::select(negative, F(kDown[i]), F(kUp[i])), p);
    a = simd::select(take, a - F(kSteps[i]), a);
  }
  return p;
}

// e^y = 2^(y log₂ e), for y log₂ e in exp2_lanes's range.
template <class F>
inline F exp_lanes(F y) {
  return exp2_lanes(y * F(1.44269504088896340736f));
}

// x^y for x ≥ 0 and y > 0: 2^(y log₂ x), 0 where x is 0 (or negative).
template <class F>
inline F pow_lanes(F x, F y) {
  return simd::select(x > F(0.0f), exp2_lanes(y * log2_lanes(x)), F(0.0f));
}

// cos(x) for |x| ≤ 8192 (clamped there; the thin film's phases stay below 100). x is
// reduced to r = x − k·π/2, |r| ≤ π/4, k = round(x · 2/π) (by 1.5 · 2²³ as exp2_lanes),
// with π/2 in three parts (Cody & Waite 1980: k · P1 and k · P2 exact for |k| < 2¹³), then
// cos r or sin r by Taylor series to r⁸ and r⁹ (errors below 3·10⁻⁸), by the quadrant k
// mod 4.
template <class F>
inline F cos_lanes(F x) {
  const F one(1.0f), zero(0.0f);
  x = simd::min(F(8192.0f), simd::max(F(-8192.0f), x));
  const F magic(12582912.0f);  // 1.5 · 2²³
  const F k = (x * F(0.636619772367581343076f) + magic) - magic;
  const F r = ((x - k * F(1.5703125f)) - k * F(4.837512969970703125e-4f)) - k * F(7.549789948768648e-8f);
  // q = k mod 4 in {0, 1, 2, 3}: k − 4 floor(k / 4), the floor by rounding and a step down.
  const F quarter = k * F(0.25f);
  F fl = (quarter + magic) - magic;
  fl = simd::select(fl > quarter, fl - one, fl);
  const F q = k - fl * F(4.0f);
  const F z = r * r;
  const F c = one - z * (F(0.5f) - z * (F(1.0f / 24.0f) - z * (F(1.0f / 720.0f) - z * F(1.0f / 40320.0f))));
  const F s = r * (one - z * (F(1.0f / 6.0f) - z * (F(1.0f / 120.0f) - z * (F(1.0f / 5040.0f) - z * F(1.0f / 362880.0f)))));
  // q = 0: cos r, 1: −sin r, 2: −cos r, 3: sin r.
  F out = simd::select(q > F(2.5f), s, zero - c);
  out = simd::select(q > F(1.5f), out, zero - s);
  return simd::select(q > F(0.5f), out, c);
}

// The double forms: dmath's, for the tables built in double and the tests' oracles.
inline double log2_lanes(double x) { return dmath::log(x) / dmath::log(2.0); }
inline double exp2_lanes(double y) { return dmath::exp2(y); }
inline double exp_lanes(double y) { return dmath::exp(y); }
inline double pow_lanes(double x, double y) { return x > 0.0 ? dmath::pow(x, y) : 0.0; }
inline double cos_lanes(double x) { return dmath::cos(x); }

}  // namespace softpbr::pbr
