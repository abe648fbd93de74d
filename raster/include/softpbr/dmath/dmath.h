// softpbr/dmath/dmath.h — deterministic elementary functions.
//
// Every function here is built from IEEE-754 basic operations (+, −, ×, ÷, sqrt) in a
// fixed order, so it returns the same bits on every compiler, libm and CPU (docs/design.md, "Determinism").
// Use them wherever a value can reach an image: libm's sin/cos/pow may differ in the last
// bit between platforms. All work in double; callers round to float where they store.
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

namespace softpbr::dmath {

inline constexpr double kPi = 3.141592653589793238462643383279502884;

namespace detail {
// sin and cos of r for |r| <= π/4 by their Taylor series to the r^17 / r^16 term:
// the first omitted term is below (π/4)^19/19! ≈ 1.3e-19, far under double's 2^-53.
constexpr double sin_kernel(double r) {
  const double r2 = r * r;
  double p = 1.0 / 355687428096000.0;                    // 1/17!
  p = p * r2 - 1.0 / 1307674368000.0;                    // 1/15!
  p = p * r2 + 1.0 / 6227020800.0;                       // 1/13!
  p = p * r2 - 1.0 / 39916800.0;                         // 1/11!
  p = p * r2 + 1.0 / 362880.0;                           // 1/9!
  p = p * r2 - 1.0 / 5040.0;                             // 1/7!
  p = p * r2 + 1.0 / 120.0;                              // 1/5!
  p = p * r2 - 1.0 / 6.0;                                // 1/3!
  return r + r * r2 * p;
}
constexpr double cos_kernel(double r) {
  const double r2 = r * r;
  double p = 1.0 / 20922789888000.0;                     // 1/16!
  p = p * r2 - 1.0 / 87178291200.0;                      // 1/14!
  p = p * r2 + 1.0 / 479001600.0;                        // 1/12!
  p = p * r2 - 1.0 / 3628800.0;                          // 1/10!
  p = p * r2 + 1.0 / 40320.0;                            // 1/8!
  p = p * r2 - 1.0 / 720.0;                              // 1/6!
  p = p * r2 + 1.0 / 24.0;                               // 1/4!
  p = p * r2 - 0.5;                                      // 1/2!
  return 1.0 + r2 * p;
}
// Round to nearest integer (ties away from zero) with basic operations only; exact for
// |x| < 2^52.
constexpr double round_int(double x) {
  return x >= 0 ? static_cast<double>(static_cast<std::int64_t>(x + 0.5))
                : -static_cast<double>(static_cast<std::int64_t>(-x + 0.5));
}
// Cody–Waite reduction: x = k·π/2 + r with π/2 split into three parts so that k·part is
// exact for |k| < 2^20; accurate for |x| up to about 1e6, which covers angles in scenes.
struct Reduced {
  double r;
  std::int64_t quadrant;
};
constexpr Reduced reduce(double x) {
  constexpr double kTwoOverPi = 0.636619772367581343075535053490057448;
  constexpr double kPio2_1 = 1.57079632673412561417e+00;  // first 33 bits of π/2
  constexpr double kPio2_2 = 6.07710050630396597660e-11;  // next 33 bits
  constexpr double kPio2_3 = 2.02226624879595063154e-21;  // π/2 − (kPio2_1 + kPio2_2)
  const double k = round_int(x * kTwoOverPi);
  const double r = ((x - k * kPio2_1) - k * kPio2_2) - k * kPio2_3;
  return {r, static_cast<std::int64_t>(k)};
}
// p · 2^k for |k| ≤ 1075, in two steps so that subnormal results and k = 1024 stay exact.
constexpr double scale_pow2(double p, std::int64_t k) {
  const std::int64_t k1 = k / 2, k2 = k - k1;
  const double s1 = std::bit_cast<double>(static_cast<std::uint64_t>(k1 + 1023) << 52);
  const double s2 = std::bit_cast<double>(static_cast<std::uint64_t>(k2 + 1023) << 52);
  return p * s1 * s2;
}

}  // namespace detail

// sin(x), accurate to a few ulp for |x| <= 1e6; NaN for non-finite x.
constexpr double sin(double x) {
  if (!(x - x == 0.0)) return x - x;  // NaN or ±Inf → NaN
  const auto [r, q] = detail::reduce(x);
  switch (q & 3) {
    case 0: return detail::sin_kernel(r);
    case 1: return detail::cos_kernel(r);
    case 2: return -detail::sin_kernel(r);
    default: return -detail::cos_kernel(r);
  }
}

// cos(x), accurate to a few ulp for |x| <= 1e6; NaN for non-finite x.
constexpr double cos(double x) {
  if (!(x - x == 0.0)) return x - x;
  const auto [r, q] = detail::reduce(x);
  switch (q & 3) {
    case 0: return detail::cos_kernel(r);
    case 1: return -detail::sin_kernel(r);
    case 2: return -detail::cos_kernel(r);
    default: return detail::sin_kernel(r);
  }
}

// tan(x) = sin(x)/cos(x): one correctly rounded division of two deterministic values.
constexpr double tan(double x) { return sin(x) / cos(x); }

// e^x, accurate to a few ulp; 0 below about −745, +Inf above about 709.78, NaN for NaN.
constexpr double exp(double x) {
  if (x != x) return x;
  if (x > 709.782712893384) return std::numeric_limits<double>::infinity();
  if (x < -745.1332191019412) return 0.0;
  // x = k·ln2 + r, |r| ≤ ln2/2, ln 2 split so k·kLn2Hi is exact.
  constexpr double kLn2Hi = 6.93147180369123816490e-01;
  constexpr double kLn2Lo = 1.90821492927058770002e-10;
  constexpr double kInvLn2 = 1.44269504088896338700e+00;
  const double k = detail::round_int(x * kInvLn2);
  const double r = (x - k * kLn2Hi) - k * kLn2Lo;
  // Taylor series of e^r to r^18/18!: the first omitted term is below 0.35^19/19! ≈ 3e-26.
  double p = 1.0 / 6402373705728000.0;  // 1/18!
  constexpr double kInvFactorial[] = {1.0 / 355687428096000.0, 1.0 / 20922789888000.0, 1.0 / 1307674368000.0,
                                      1.0 / 87178291200.0,     1.0 / 6227020800.0,     1.0 / 479001600.0,
                                      1.0 / 39916800.0,        1.0 / 3628800.0,        1.0 / 362880.0,
                                      1.0 / 40320.0,           1.0 / 5040.0,           1.0 / 720.0,
                                      1.0 / 120.0,             1.0 / 24.0,             1.0 / 6.0,
                                      1.0 / 2.0,               1.0,                    1.0};
  for (double c : kInvFactorial) p = p * r + c;
  return detail::scale_pow2(p, static_cast<std::int64_t>(k));
}

// 2^x, accurate to a few ulp and exact for integer x. The integer part n is split off
// first: scaling x by ln 2 up front (e^(x ln 2)) would turn the rounding of that product
// into a relative error of |x ln 2| · 2⁻⁵³, up to 8e-14 near |x| = 1000.
constexpr double exp2(double x) {
  if (x != x) return x;
  if (x >= 1024.0) return std::numeric_limits<double>::infinity();
  if (x < -1075.0) return 0.0;
  const double n = detail::round_int(x);
  const double f = x - n;  // exact, |f| ≤ 1/2
  const double p = exp(f * 0.693147180559945309417232121458176568);
  return detail::scale_pow2(p, static_cast<std::int64_t>(n));
}

// Natural logarithm, accurate to a few ulp; −Inf at 0, NaN below 0 or for NaN.
constexpr double log(double x) {
  if (x != x || x < 0.0) return std::numeric_limits<double>::quiet_NaN();
  if (x == 0.0) return -std::numeric_limits<double>::infinity();
  if (x == std::numeric_limits<double>::infinity()) return x;
  // x = m · 2^e with m in [√½, √2), read from the bits (subnormals scaled up first).
  std::int64_t e = 0;
  if (x < 2.2250738585072014e-308) {
    x *= 18014398509481984.0;  // 2^54
    e = -54;
  }
  const auto bits = std::bit_cast<std::uint64_t>(x);
  e += static_cast<std::int64_t>((bits >> 52) & 0x7ff) - 1023;
  double m = std::bit_cast<double>((bits & 0x000fffffffffffffull) | 0x3ff0000000000000ull);
  if (m > 1.4142135623730951) {
    m *= 0.5;
    ++e;
  }
  // ln m = 2 atanh(s), s = (m − 1)/(m + 1), |s| ≤ 0.1716: the series to s^25 leaves < 1e-20.
  const double s = (m - 1.0) / (m + 1.0);
  const double s2 = s * s;
  double p = 1.0 / 25.0;
  for (int n = 23; n >= 1; n -= 2) p = p * s2 + 1.0 / n;
  constexpr double kLn2Hi = 6.93147180369123816490e-01;
  constexpr double kLn2Lo = 1.90821492927058770002e-10;
  const double de = static_cast<double>(e);
  return de * kLn2Hi + (2.0 * s * p + de * kLn2Lo);
}

// x^y for x ≥ 0 as exp(y · ln x): relative error about |y ln x| · 1e-16, ample for
// gamma curves and exposure. 0^y = 0 for y > 0, 1 for y = 0; NaN for x < 0.
constexpr double pow(double x, double y) {
  if (y == 0.0) return 1.0;
  if (x == 0.0) return y > 0.0 ? 0.0 : std::numeric_limits<double>::infinity();
  return exp(y * log(x));
}

constexpr double radians(double degrees) { return degrees * (kPi / 180.0); }

// ---- Inverse trigonometry (not constexpr: std::sqrt and std::fabs are not, before C++26;
// both are exact or correctly rounded, so as deterministic as the basic operations) ----

// atan(t) for 0 ≤ t ≤ 1. Two half-angle steps, atan t = 2 atan(t / (1 + √(1 + t²))), bring t
// down to at most tan(π/16) ≈ 0.199; the Taylor series to t^25 then leaves below
// 0.2^27/27 ≈ 5e-21, far under double's 2^-53.
inline double atan_unit(double t) {
  for (int k = 0; k < 2; ++k) t = t / (1.0 + std::sqrt(1.0 + t * t));
  const double t2 = t * t;
  double p = 1.0 / 25.0;  // + t^24/25
  for (int k = 11; k >= 0; --k) p = p * t2 + (k % 2 == 0 ? 1.0 : -1.0) / (2 * k + 1);
  return 4.0 * t * p;
}

// atan2(y, x) in [−π, π], as std::atan2 for y ≠ 0, except that on the axes the sign of a
// zero does not count: atan2(±0, x < 0) = π, atan2(±0, x > 0) = 0 and atan2(±0, ±0) = 0.
inline double atan2(double y, double x) {
  const double ax = std::fabs(x), ay = std::fabs(y);
  if (ax == 0.0 && ay == 0.0) return 0.0;
  double a = ay <= ax ? atan_unit(ay / ax) : kPi / 2 - atan_unit(ax / ay);
  if (x < 0.0) a = kPi - a;
  return y < 0.0 ? -a : a;
}

// The angle between two non-zero vectors by Kahan's formula 2·atan2(|â − b̂|, |â + b̂|)
// ("Mindless", 2006, §12), accurate near 0 and π where acos of a dot product is not.
inline double angle_between(const glm::dvec3& a, const glm::dvec3& b) {
  const glm::dvec3 ua = a / std::sqrt(glm::dot(a, a)), ub = b / std::sqrt(glm::dot(b, b));
  const glm::dvec3 d = ua - ub, s = ua + ub;
  return 2.0 * atan2(std::sqrt(glm::dot(d, d)), std::sqrt(glm::dot(s, s)));
}

}  // namespace softpbr::dmath
