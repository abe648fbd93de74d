// The lanes kernels of pbr::ToneMapper::encode (4 lanes, AVX2, AVX-512: tonemap.h) against
// the plain per-pixel kernel (EncodeKernel::Scalar), byte for byte: every operator, the
// sRGB curve and gammas from 0.05 to 20, several exposures, over every float bit pattern
// in [0, 1.5) at a stride, every threshold and its neighbours, and the special values
// (NaN, ±Inf, ±0, negatives, denormals, huge), in colour and alpha; and rectangles of
// every width around the lane counts, leaving the bytes outside them alone.
#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include <doctest/doctest.h>
#include <glm/vec4.hpp>

#include "softpbr/pbr/tonemap.h"
#include "softpbr/raster/target.h"

namespace pbr = softpbr::pbr;
namespace raster = softpbr::raster;

namespace {

constexpr pbr::ToneMap kOps[] = {pbr::ToneMap::None, pbr::ToneMap::Reinhard, pbr::ToneMap::Aces, pbr::ToneMap::Neutral};
// 0 is sRGB; 0.05 needs more steps than kMaxSteps (binary search); from ~17 on the first
// thresholds underflow to 0, so −0 and +0 count them.
constexpr float kGammas[] = {0.0f, 0.05f, 0.5f, 1.0f, 2.2f, 2.4f, 10.0f, 20.0f};
// Exposure 0 (the curves' thresholds hit exactly) for every curve and operator, and one of
// the others in turn (a table of all of them takes seconds).
constexpr float kOtherExposures[] = {-2.5f, 1.0f, 13.0f};
constexpr pbr::EncodeKernel kLanesKernels[] = {pbr::EncodeKernel::Lanes4, pbr::EncodeKernel::Avx2,
                                               pbr::EncodeKernel::Avx512};

std::string kernel_name(pbr::EncodeKernel k) {
  switch (k) {
    case pbr::EncodeKernel::Scalar: return "scalar";
    case pbr::EncodeKernel::Lanes4: return "lanes4";
    case pbr::EncodeKernel::Avx2: return "avx2";
    default: return "avx512";
  }
}

float from_bits(std::uint32_t b) { return std::bit_cast<float>(b); }

// The values every channel sees: float bit patterns in [0, 1.5) at a stride (prime, so
// every low-bit pattern turns up), every threshold of every curve tested and the floats
// next to it, the specials, and the negatives of a sample of all these.
std::vector<float> test_values() {
  std::vector<float> v;
  constexpr std::uint32_t kStride = 8209;  // ~131,000 values below 1.5
  for (std::uint32_t b = 0; b < 0x3fc00000u; b += kStride) v.push_back(from_bits(b));
  for (float gamma : kGammas)
    for (float t : pbr::transfer_thresholds(gamma))
      for (float x : {t, std::nextafter(t, 0.0f), std::nextafter(t, 2.0f)}) v.push_back(x);
  const float inf = std::numeric_limits<float>::infinity();
  for (float x : {std::numeric_limits<float>::quiet_NaN(), -std::numeric_limits<float>::quiet_NaN(),
                  std::numeric_limits<float>::signaling_NaN(), from_bits(0x7f800001u), from_bits(0xffc12345u), inf,
                  -inf, 0.0f, -0.0f, std::numeric_limits<float>::denorm_min(), std::numeric_limits<float>::min(),
                  1.0f, std::nextafter(1.0f, 0.0f), std::nextafter(1.0f, 2.0f), 7.24f, 1e9f,
                  std::nextafter(1e9f, 0.0f), std::nextafter(1e9f, 2e9f), 1e19f, 1e20f, 1e30f,
                  std::numeric_limits<float>::max()})
    v.push_back(x);
  const std::size_t n = v.size();
  for (std::size_t i = 0; i < n; i += 7) v.push_back(-v[i]);
  return v;
}

// Pixels from the values: the first `values.size()` grey (r = g = b, the curves straight),
// the next as many mixed (each channel from a different place in the list: PBR Neutral
// mixes channels), alpha from yet another place. Width 1021: rows end at every lane offset.
raster::Target test_target(const std::vector<float>& values) {
  const std::size_t n = values.size();
  const int width = 1021;
  const int height = static_cast<int>((2 * n + width - 1) / width);
  raster::Target t(width, height);
  t.clear({0.5f, 0.25f, 2.0f, 0.5f});
  glm::vec4* px = t.colors().data();
  for (std::size_t i = 0; i < n; ++i) {
    px[i] = {values[i], values[i], values[i], values[(i * 31 + 3) % n]};
    px[n + i] = {values[i], values[(i * 7919 + 1) % n], values[(i * 104729 + 2) % n], values[(i * 13 + 5) % n]};
  }
  return t;
}

raster::Image8 blank_image(const raster::Target& t, std::uint8_t fill) {
  raster::Image8 img;
  img.width = t.width();
  img.height = t.height();
  img.rgba.assign(t.colors().size() * 4, fill);
  return img;
}

// The first differing pixel of two images, or −1.
long first_difference(const raster::Image8& a, const raster::Image8& b) {
  const auto [pa, pb] = std::mismatch(a.rgba.begin(), a.rgba.end(), b.rgba.begin());
  return pa == a.rgba.end() ? -1 : static_cast<long>((pa - a.rgba.begin()) / 4);
}

}  // namespace

TEST_CASE("every lanes kernel encodes every operator, curve and exposure byte for byte as the scalar kernel") {
  const std::vector<float> values = test_values();
  REQUIRE(values.size() > 130000);
  const raster::Target target = test_target(values);
  int kernels_run = 0, turn = 0;
  for (float gamma : kGammas)
    for (pbr::ToneMap op : kOps)
      for (float exposure : {0.0f, kOtherExposures[turn++ % std::size(kOtherExposures)]}) {
        const pbr::ToneMapper mapper({exposure, op, gamma});
        raster::Image8 want = blank_image(target, 0xa5);
        mapper.encode(target, 0, 0, target.width(), target.height(), want, pbr::EncodeKernel::Scalar);
        for (pbr::EncodeKernel kernel : kLanesKernels) {
          if (!pbr::ToneMapper::supported(kernel)) continue;
          ++kernels_run;
          raster::Image8 got = blank_image(target, 0x5a);
          mapper.encode(target, 0, 0, target.width(), target.height(), got, kernel);
          const long at = first_difference(got, want);
          CAPTURE(kernel_name(kernel));
          CAPTURE(pbr::tone_map_name(op));
          CAPTURE(gamma);
          CAPTURE(exposure);
          if (at >= 0) {
            const glm::vec4 c = target.colors()[static_cast<std::size_t>(at)];
            const auto byte = [&](const raster::Image8& img, int k) { return int{img.rgba[static_cast<std::size_t>(at) * 4 + k]}; };
            FAIL_CHECK("pixel " << at << " (" << c.r << ", " << c.g << ", " << c.b << ", " << c.a << "): got " << byte(got, 0)
                                << " " << byte(got, 1) << " " << byte(got, 2) << " " << byte(got, 3) << ", want "
                                << byte(want, 0) << " " << byte(want, 1) << " " << byte(want, 2) << " " << byte(want, 3));
          }
        }
      }
  // Lanes4 runs everywhere; AVX2 and AVX-512 where the CPU has them.
  CHECK(kernels_run >= static_cast<int>(std::size(kGammas) * std::size(kOps) * 2));
}

TEST_CASE("the lanes kernels write exactly the rectangle asked for, at every width around the lane counts") {
  const std::vector<float> values = test_values();
  raster::Target target(53, 9);
  for (std::size_t i = 0; i < target.colors().size(); ++i) {
    const std::size_t j = i * 2654435761u % values.size();
    target.colors()[i] = {values[j], values[(j + 1) % values.size()], values[(j + 2) % values.size()], values[(j + 3) % values.size()]};
  }
  for (pbr::ToneMap op : kOps) {
    const pbr::ToneMapper mapper({0.0f, op, 0.0f});
    for (int x0 : {0, 1, 3, 5})
      for (int width = 0; width <= 40; ++width)
        for (int y0 : {0, 2}) {
          const int x1 = std::min(x0 + width, target.width()), y1 = y0 + 3;
          raster::Image8 want = blank_image(target, 0x77);
          mapper.encode(target, x0, y0, x1, y1, want, pbr::EncodeKernel::Scalar);
          for (pbr::EncodeKernel kernel : kLanesKernels) {
            if (!pbr::ToneMapper::supported(kernel)) continue;
            raster::Image8 got = blank_image(target, 0x77);  // outside the rectangle: still 0x77
            mapper.encode(target, x0, y0, x1, y1, got, kernel);
            CAPTURE(kernel_name(kernel));
            CAPTURE(pbr::tone_map_name(op));
            CAPTURE(x0);
            CAPTURE(width);
            CAPTURE(y0);
            CHECK(first_difference(got, want) == -1);
          }
        }
  }
  // The default encode() is the widest kernel.
  const pbr::ToneMapper mapper({0.5f, pbr::ToneMap::Aces, 2.2f});
  raster::Image8 a = blank_image(target, 0), b = blank_image(target, 0);
  mapper.encode(target, 0, 0, target.width(), target.height(), a);
  mapper.encode(target, 0, 0, target.width(), target.height(), b, pbr::ToneMapper::widest_kernel());
  CHECK(a.rgba == b.rgba);
}

TEST_CASE("multisampled targets: every lanes kernel resolves (tone-mapped) and encodes byte for byte as the scalar one") {
  const std::vector<float> values = test_values();
  for (int samples : {4, 8}) {
    // Samples of one pixel differ (each from its own place in the list) or agree (every
    // third pixel, and every pixel of the first three rows, so that whole sets of lanes
    // agree: the case of pixels inside a surface).
    raster::Target target(53, 9, samples);
    const std::size_t plane = static_cast<std::size_t>(target.width()) * target.height();
    for (std::size_t i = 0; i < plane; ++i)
      for (int s = 0; s < samples; ++s) {
        const bool agree = i % 3 == 0 || i < 3 * 53;
        const std::size_t j = (i * 2654435761u + (agree ? 0 : static_cast<std::size_t>(s) * 7919)) % values.size();
        target.colors()[static_cast<std::size_t>(s) * plane + i] = {
            values[j], values[(j + 1) % values.size()], values[(j + 2) % values.size()],
            values[(j + 3) % values.size()]};
      }
    int kernels_run = 0;
    for (pbr::ToneMap op : kOps)
      for (float gamma : {0.0f, 2.2f})
        for (float exposure : {0.0f, 1.0f}) {
          const pbr::ToneMapper mapper({exposure, op, gamma});
          for (const std::array<int, 4>& rect : {std::array{0, 53, 0, 9}, std::array{1, 18, 2, 5}, std::array{3, 40, 4, 9}}) {
            // Plain ints, not structured bindings: Clang 14 cannot capture those in INFO's lambda.
            const int x0 = rect[0], x1 = rect[1], y0 = rect[2], y1 = rect[3];
            raster::Image8 want = blank_image(target, 0x77);
            mapper.encode(target, x0, y0, x1, y1, want, pbr::EncodeKernel::Scalar);
            for (pbr::EncodeKernel kernel : kLanesKernels) {
              if (!pbr::ToneMapper::supported(kernel)) continue;
              ++kernels_run;
              raster::Image8 got = blank_image(target, 0x77);
              mapper.encode(target, x0, y0, x1, y1, got, kernel);
              INFO("kernel ", kernel_name(kernel), ", ", pbr::tone_map_name(op), ", ", samples, " samples, gamma ",
                   gamma, ", exposure ", exposure, ", x ", x0, "..", x1, ", y ", y0, "..", y1);
              CHECK(first_difference(got, want) == -1);
            }
          }
        }
    CHECK(kernels_run >= static_cast<int>(std::size(kOps)) * 2 * 2 * 3);
  }
}

TEST_CASE("the tone-mapped resolve of pixels whose samples agree is their pairwise mean, computed (4v overflows past FLT_MAX/4)") {
  const float big = std::numeric_limits<float>::max();
  const float inf = std::numeric_limits<float>::infinity();
  const std::vector<float> values = {0.0f, -0.0f, 0.25f, 1.0f, 7.24f, 1e30f, 8.5e37f, 9e37f, 1e38f, big, inf,
                                     std::numeric_limits<float>::denorm_min(), -1e38f,
                                     std::numeric_limits<float>::quiet_NaN()};
  for (int samples : {4, 8}) {
    CAPTURE(samples);
    // 64 pixels a row (whole sets of every lane width), all samples of a pixel equal.
    raster::Target target(64, static_cast<int>(values.size()), samples);
    const std::size_t plane = static_cast<std::size_t>(target.width()) * target.height();
    for (std::size_t i = 0; i < plane; ++i) {
      const float v = values[i / 64];
      for (int s = 0; s < samples; ++s) target.colors()[static_cast<std::size_t>(s) * plane + i] = {v, v, v, v};
    }
    // No exposure; ToneMap::None only clamps colour to [0, 1] (alpha is never tone mapped):
    // the resolve is the box mean of the clamped v, and of v itself for alpha.
    const pbr::ToneMapper mapper({0.0f, pbr::ToneMap::None, 2.2f});
    std::vector<glm::vec4> out(plane);
    mapper.resolve(target, 0, 0, target.width(), target.height(), out.data(), 64);
    for (std::size_t k = 0; k < values.size(); ++k) {
      const float v = values[k];
      const auto mean = [&](float x) {
        const float quad = (x + x) + (x + x);
        return samples == 4 ? quad * 0.25f : (quad + quad) * 0.125f;
      };
      const float want_rgb = mean(std::min(std::max(v, 0.0f), 1.0f)), want_a = mean(v);
      CAPTURE(v);
      // The cases a shortcut to the sample itself would get wrong.
      if (v == 1e38f || v == -1e38f) CHECK(std::isinf(want_a));
      if (v == 7.24f) CHECK(want_a == v);
      for (int x = 0; x < 64; ++x) {
        const glm::vec4 got = out[k * 64 + static_cast<std::size_t>(x)];
        if (std::isnan(v)) {  // a NaN's payload is the CPU's business
          CHECK(std::isnan(got.r));
          CHECK(std::isnan(got.a));
          continue;
        }
        CHECK(std::memcmp(&got.r, &want_rgb, sizeof want_rgb) == 0);
        CHECK(std::memcmp(&got.a, &want_a, sizeof want_a) == 0);
      }
    }
  }
}

TEST_CASE("the code of a value is the number of thresholds at or below it (0 for NaN), for every curve") {
  const std::vector<float> values = test_values();
  for (float gamma : kGammas) {
    const pbr::ToneMapper mapper({0.0f, pbr::ToneMap::None, gamma});
    const std::array<float, 255> t = pbr::transfer_thresholds(gamma);
    CAPTURE(gamma);
    long mismatches = 0;
    for (float v : values) {
      const long want = std::isnan(v) ? 0 : std::upper_bound(t.begin(), t.end(), v) - t.begin();
      if (mapper.encode(v) != want) ++mismatches;
    }
    CHECK(mismatches == 0);
    // The kernel each curve takes (tonemap.h), so that the test above covers all three:
    // packed table (≤ 1 step) for sRGB and the usual gammas, steps for 0.5 and 20, binary
    // search for 0.05.
    if (gamma == 0.0f || (gamma >= 1.0f && gamma <= 10.0f)) CHECK(mapper.code_steps() == 1);
    if (gamma == 0.5f) CHECK(mapper.code_steps() == 2);
    if (gamma == 20.0f) CHECK(mapper.code_steps() == 3);
    if (gamma == 0.05f) CHECK(mapper.code_steps() == -1);
  }
}
