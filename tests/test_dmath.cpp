// Deterministic math against libm, and the sRGB encoder against the exact curve.
#include <bit>
#include <cmath>
#include <cstdint>
#include <vector>

#include <doctest/doctest.h>
#include <glm/vec3.hpp>

#include "softpbr/raster/color.h"
#include "softpbr/dmath/dmath.h"

namespace dm = softpbr::dmath;

TEST_CASE("dmath sin/cos/tan agree with libm to a few ulp over a wide range") {
  double worst = 0;
  for (int i = -200000; i <= 200000; ++i) {
    const double x = i * 0.00123456789;  // about ±247 rad
    const double ref[3] = {std::sin(x), std::cos(x), std::tan(x)};
    const double got[3] = {dm::sin(x), dm::cos(x), dm::tan(x)};
    for (int k = 0; k < 3; ++k) {
      const double err = std::fabs(got[k] - ref[k]) / std::max(std::fabs(ref[k]), 1e-300);
      if (std::fabs(ref[k]) > 1e-6) worst = std::max(worst, err);
      CHECK(std::fabs(got[k] - ref[k]) <= 4e-16 * std::max(1.0, std::fabs(ref[k])) + 1e-15);
    }
  }
  MESSAGE("worst relative error " << worst);
  CHECK(worst < 1e-12);
  CHECK(std::isnan(dm::sin(INFINITY)));
  CHECK(std::isnan(dm::cos(NAN)));
  CHECK(dm::sin(0.0) == 0.0);
  CHECK(dm::cos(0.0) == 1.0);
}

TEST_CASE("dmath is usable at compile time") {
  static_assert(dm::cos(0.0) == 1.0);
  static_assert(dm::sin(dm::kPi / 2) > 0.9999999999);
}

TEST_CASE("dmath atan2 agrees with libm within 6 ulp in every quadrant, on the axes and at extreme ratios") {
  std::vector<double> coords = {1.0, 0.5, 2.0, 1e-300, 1e300, 3.0, 0.1, 1.0 + 1e-15, 7.25, 1e-10, 123456.789};
  for (int i = 1; i <= 64; ++i) coords.push_back(i * 0.173);
  int compared = 0;
  double worst = 0;
  for (double ay : coords)
    for (double ax : coords)
      for (double sy : {1.0, -1.0})
        for (double sx : {1.0, -1.0}) {
          const double y = sy * ay, x = sx * ax;
          const double got = dm::atan2(y, x), want = std::atan2(y, x);
          const double ulps = std::fabs(got - want) / (std::nextafter(std::fabs(want), INFINITY) - std::fabs(want));
          worst = std::max(worst, ulps);
          CHECK_MESSAGE(ulps <= 6, "atan2(" << y << ", " << x << ") = " << got << ", libm " << want);
          ++compared;
        }
  MESSAGE(compared << " atan2 values, worst " << worst << " ulp from libm");
  // The axes: y = 0 of either sign gives 0 or π (not −π); x = ±0 gives ±π/2.
  for (double zero : {0.0, -0.0}) {
    CHECK(dm::atan2(zero, 1.0) == 0.0);
    CHECK(dm::atan2(zero, -1.0) == dm::kPi);
    CHECK(dm::atan2(zero, zero) == 0.0);
    CHECK(dm::atan2(zero, -zero) == 0.0);
    CHECK(dm::atan2(1.0, zero) == dm::kPi / 2);
    CHECK(dm::atan2(-1.0, zero) == -dm::kPi / 2);
  }
}

TEST_CASE("dmath atan2 and angle_between return the same bits as mesh.cpp's functions they replaced") {
  // Taken from pbr/src/mesh.cpp's atan2/angle_between before they moved here.
  struct Atan2Pin {
    double y, x;
    std::uint64_t bits;
  };
  const Atan2Pin atan2_pins[] = {
      {0x0p+0, 0x1p+0, 0x0000000000000000ull},
      {-0x0p+0, -0x1p+0, 0x400921fb54442d18ull},
      {0x1p+0, 0x0p+0, 0x3ff921fb54442d18ull},
      {-0x1p+0, -0x0p+0, 0xbff921fb54442d18ull},
      {0x1p-1, 0x1p+1, 0x3fcf5b75f92c80ddull},
      {-0x1p-1, -0x1p+1, 0xc0072c43f4b1650aull},
      {0x1.8p+1, 0x1p-2, 0x3ff7cd6f6dc59db4ull},
      {-0x1.8p+1, -0x1.8p-1, 0xbffd0d6a1369bd34ull},
      {0x1.56e1fc2f8f359p-997, 0x1p+0, 0x01a56e1fc2f8f359ull},
      {0x1.4p+1, 0x1.4p+1, 0x3fe921fb54442d19ull},
      {-0x1.dp+2, -0x1.7e43c8800759cp+996, 0xc00921fb54442d18ull},
      {0x1p+0, 0x1.56e1fc2f8f359p-997, 0x3ff921fb54442d18ull},
      {0x1.999999999999ap-4, 0x1.3333333333333p-2, 0x3fd4978fa3269ee2ull},
  };
  for (const Atan2Pin& p : atan2_pins) {
    CAPTURE(p.y);
    CAPTURE(p.x);
    CHECK(std::bit_cast<std::uint64_t>(dm::atan2(p.y, p.x)) == p.bits);
  }
  struct AnglePin {
    glm::dvec3 a, b;
    std::uint64_t bits;
  };
  const AnglePin angle_pins[] = {
      {{0x1p+0, 0x0p+0, 0x0p+0}, {0x0p+0, 0x1p+0, 0x0p+0}, 0x3ff921fb54442d19ull},
      {{0x1p+0, 0x0p+0, 0x0p+0}, {-0x1p+0, 0x1.19799812dea11p-40, 0x0p+0}, 0x400921fb5444244cull},
      {{0x1p+0, 0x1p+1, 0x1.8p+1}, {-0x1p+1, 0x1p-1, 0x1p+0}, 0x3ff55d8fa42ec673ull},
      {{0x1p+0, 0x0p+0, 0x0p+0}, {0x1p+0, 0x1.19799812dea11p-40, 0x0p+0}, 0x3d719799812dea11ull},
      {{0x1.3333333333333p-2, -0x1.999999999999ap-3, 0x1.4p+2}, {-0x1p+2, 0x1p+0, 0x1.999999999999ap-4}, 0x3ff9d456d7984882ull},
      {{0x1p+0, 0x1.12e0be826d695p-30, 0x0p+0}, {0x1.8p+1, 0x0p+0, 0x0p+0}, 0x3e112e0be826d695ull},
  };
  for (const AnglePin& p : angle_pins) CHECK(std::bit_cast<std::uint64_t>(dm::angle_between(p.a, p.b)) == p.bits);
  // Kahan's formula stays accurate near 0 and π, where acos of a dot product loses half the digits.
  CHECK(dm::angle_between({1, 0, 0}, {1, 1e-12, 0}) == doctest::Approx(1e-12).epsilon(1e-12));
  CHECK(dm::kPi - dm::angle_between({1, 0, 0}, {-1, 1e-12, 0}) == doctest::Approx(1e-12).epsilon(1e-9));
}

TEST_CASE("sRGB 8-bit encoding is the correctly rounded exact curve") {
  using softpbr::raster::linear_to_srgb8;
  CHECK(linear_to_srgb8(0.0f) == 0);
  CHECK(linear_to_srgb8(1.0f) == 255);
  CHECK(linear_to_srgb8(-1.0f) == 0);
  CHECK(linear_to_srgb8(2.0f) == 255);
  CHECK(linear_to_srgb8(NAN) == 0);
  CHECK(linear_to_srgb8(0.5f) == 188);  // 0.5 → 0.7354 → 187.5… rounds to 188
  // Against the curve in double through libm, away from the rounding ties.
  int mismatches = 0;
  for (int i = 0; i <= 100000; ++i) {
    const float x = i / 100000.0f;
    const double e = x <= 0.0031308 ? x * 12.92 : 1.055 * std::pow(static_cast<double>(x), 1 / 2.4) - 0.055;
    const double code = e * 255.0;
    if (std::fabs(code - std::floor(code) - 0.5) < 1e-4) continue;  // too close to a tie to judge
    if (linear_to_srgb8(x) != static_cast<int>(std::lround(code))) ++mismatches;
  }
  CHECK(mismatches == 0);
  // The decoding function used for the thresholds matches libm's pow.
  for (int k = 0; k <= 255; ++k) {
    const double e = k / 255.0;
    const double ref = e <= 0.04045 ? e / 12.92 : std::pow((e + 0.055) / 1.055, 2.4);
    CHECK(softpbr::raster::srgb_to_linear(e) == doctest::Approx(ref).epsilon(1e-14));
  }
}
