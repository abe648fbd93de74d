// softpbr::golden comparisons: the documented content hash, difference statistics, the
// heat-map diff image and the side-by-side image.
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include <doctest/doctest.h>

#include "golden_helpers.h"
#include "softpbr/golden/compare.h"

namespace golden = softpbr::golden;
namespace raster = softpbr::raster;
using namespace golden_test;

namespace {
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();
}  // namespace

TEST_CASE("content hash: FNV-1a over the documented byte sequence (values computed independently in Python)") {
  // python3: FNV-1a 64 of struct.pack('<IIII', w, h, 4, bytes_per_channel) + samples.
  CHECK(golden::content_hash(raster::Image8{1, 1, {255, 0, 0, 255}}) == 0xc9fea42538ede09eull);
  CHECK(golden::content_hash(raster::Image8{2, 1, {0, 64, 128, 255, 1, 2, 3, 4}}) == 0x40968be72aff3d7eull);
  CHECK(golden::content_hash(golden::ImageF{1, 1, {1.0f, 0.5f, 0.0f, 1.0f}}) == 0xeac930605c1bda08ull);
  CHECK(golden::hash_hex(0xc9fea42538ede09eull) == "c9fea42538ede09e");
  CHECK(golden::hash_hex(0x1ull) == "0000000000000001");
}

TEST_CASE("content hash: changes with any one bit of any sample, with the size, and with the sample type") {
  const raster::Image8 base = pattern8(4, 4);
  const std::uint64_t h = golden::content_hash(base);
  for (std::size_t i = 0; i < base.rgba.size(); i += 5)
    for (int bit = 0; bit < 8; bit += 3) {
      raster::Image8 changed = base;
      changed.rgba[i] ^= static_cast<std::uint8_t>(1u << bit);
      CHECK(golden::content_hash(changed) != h);
    }
  // The same 64 bytes as 4x4, 2x8, 8x2 and 16x1.
  for (auto [w, hgt] : {std::pair{2, 8}, {8, 2}, {16, 1}}) CHECK(golden::content_hash(raster::Image8{w, hgt, base.rgba}) != h);
  const golden::ImageF f = golden::to_float(base);
  golden::ImageF g = f;
  g.rgba[7] = -g.rgba[7];  // a sign bit
  CHECK(golden::content_hash(g) != golden::content_hash(f));
  g = f;
  g.rgba[0] = 0.0f;  // -0 and +0 compare equal but hash differently
  golden::ImageF minus = f;
  minus.rgba[0] = -0.0f;
  CHECK(golden::content_hash(g) != golden::content_hash(minus));
  CHECK(golden::compare(g, minus).identical);
}

TEST_CASE("content hash of a Target is the hash of its colour buffer as a float image") {
  raster::Target t(5, 3);
  t.color(4, 2) = {0.25f, kNaN, -3.0f, 0.5f};
  CHECK(golden::content_hash(t) == golden::content_hash(golden::to_image(t)));
  const std::uint64_t before = golden::content_hash(t);
  t.depth(0, 0) = 0.5f;  // depth is not part of the content
  CHECK(golden::content_hash(t) == before);
}

TEST_CASE("compare: statistics of known 8-bit differences equal their hand-computed values") {
  // expected: 2x2, all samples 100. actual: pixel 0 +10 in R, pixel 1 -4 in G and +2 in A,
  // pixels 2 and 3 equal. 16 samples; diffs 10, 4, 2.
  const raster::Image8 e{2, 2, std::vector<std::uint8_t>(16, 100)};
  raster::Image8 a = e;
  a.rgba[0] = 110;
  a.rgba[5] = 96;
  a.rgba[7] = 102;
  struct Case {
    double threshold;
    std::uint64_t above;
  };
  for (const Case& c : {Case{0, 2}, {3.9, 2}, {4, 1}, {9.99, 1}, {10, 0}, {255, 0}}) {
    CAPTURE(c.threshold);
    const golden::Comparison r = golden::compare(e, a, c.threshold);
    CHECK(r.same_size());
    CHECK_FALSE(r.identical);
    CHECK(r.pixels == 4);
    CHECK(r.pixels_above == c.above);
    CHECK(r.fraction_above == doctest::Approx(c.above / 4.0));
    CHECK(r.max_abs_diff == std::array<double, 4>{10, 4, 0, 2});
    CHECK(r.max_diff() == 10);
    CHECK(r.mean_abs_diff == std::array<double, 4>{2.5, 1, 0, 0.5});
    CHECK(r.mean_abs_diff_all == doctest::Approx(16.0 / 16));
    CHECK(r.rmse == doctest::Approx(std::sqrt((100.0 + 16 + 4) / 16)));
    CHECK(r.psnr == doctest::Approx(20 * std::log10(255 / std::sqrt(120.0 / 16))));
    CHECK(r.peak == 255);
    CHECK(r.threshold == c.threshold);
  }
  const golden::Comparison same = golden::compare(e, e);
  CHECK(same.identical);
  CHECK(same.rmse == 0);
  CHECK(same.psnr == kInf);
  CHECK(same.pixels_above == 0);
  CHECK(same.describe().find("identical") != std::string::npos);
}

TEST_CASE("compare: floats are equal when their values or their bits are, a NaN against a number is infinitely far") {
  struct Case {
    float e, a;
    double diff;
  };
  const Case cases[] = {{0.0f, -0.0f, 0},   {kNaN, kNaN, 0},         {1.0f, kNaN, kInf},
                        {kNaN, 2.0f, kInf}, {0.5f, 0.25f, 0.25},     {-1.0f, 1.0f, 2},
                        {1e30f, -1e30f, 2.0 * static_cast<double>(1e30f)}, {1.0f, std::nextafter(1.0f, 2.0f), std::ldexp(1.0, -23)}};
  for (const Case& c : cases) {
    CAPTURE(c.e);
    CAPTURE(c.a);
    const golden::Comparison r = golden::compare(golden::ImageF{1, 1, {c.e, 0, 0, 1}}, golden::ImageF{1, 1, {c.a, 0, 0, 1}});
    CHECK(r.max_abs_diff[0] == c.diff);  // exact: differences of floats are exact in double
    CHECK(r.identical == (c.diff == 0));
    CHECK(r.pixels_above == (c.diff > 0 ? 1u : 0u));
    CHECK(r.peak == 1);
  }
}

TEST_CASE("compare: different sizes are a result, not an error, bad pixel data throws") {
  const golden::Comparison r = golden::compare(pattern8(4, 3), pattern8(3, 4));
  CHECK_FALSE(r.same_size());
  CHECK_FALSE(r.identical);
  CHECK(r.pixels == 0);
  CHECK(r.max_diff() == 0);
  CHECK(r.describe().find("expected 4x3, actual 3x4") != std::string::npos);
  raster::Image8 bad = pattern8(4, 3);
  bad.rgba.pop_back();
  CHECK_THROWS_AS(golden::compare(bad, pattern8(4, 3)), std::invalid_argument);
  CHECK_THROWS_AS(golden::content_hash(bad), std::invalid_argument);
  CHECK_THROWS_AS(golden::diff_image(pattern8(4, 3), bad), std::invalid_argument);
  raster::Target t1(4, 3), t2(4, 3);
  t2.color(1, 1).g = 0.5f;
  const golden::Comparison rt = golden::compare(t1, t2);
  CHECK(rt.pixels_above == 1);
  CHECK(rt.max_abs_diff[1] == 0.5);
}

TEST_CASE("diff image: black where equal, the ramp red → yellow → white by difference, white for NaN") {
  // One row: equal, then diffs 1, 2, 3 (of scale 3), and 6 (above the scale).
  const raster::Image8 e{5, 1, std::vector<std::uint8_t>(20, 50)};
  raster::Image8 a = e;
  a.rgba[4] = 51;   // pixel 1: d = 1
  a.rgba[9] = 48;   // pixel 2: d = 2
  a.rgba[15] = 53;  // pixel 3: d = 3 (alpha)
  a.rgba[16] = 56;  // pixel 4: d = 6
  struct Case {
    double scale;
    std::array<std::array<int, 3>, 5> rgb;
  };
  // s = 1/3 + 2/3 min(d/scale, 1); r = 3s, g = 3s - 1, b = 3s - 2, clamped, × 255 rounded.
  const Case cases[] = {
      {3, {{{0, 0, 0}, {255, 170, 0}, {255, 255, 85}, {255, 255, 255}, {255, 255, 255}}}},
      {6, {{{0, 0, 0}, {255, 85, 0}, {255, 170, 0}, {255, 255, 0}, {255, 255, 255}}}},
      {0, {{{0, 0, 0}, {255, 85, 0}, {255, 170, 0}, {255, 255, 0}, {255, 255, 255}}}},  // 0: the largest d (6)
      {1000, {{{0, 0, 0}, {255, 1, 0}, {255, 1, 0}, {255, 2, 0}, {255, 3, 0}}}},       // tiny d still red
  };
  for (const Case& c : cases) {
    CAPTURE(c.scale);
    const raster::Image8 d = golden::diff_image(e, a, c.scale);
    REQUIRE(d.rgba.size() == 20);
    for (int p = 0; p < 5; ++p) {
      CAPTURE(p);
      CHECK(d.rgba[4 * p + 0] == c.rgb[p][0]);
      CHECK(d.rgba[4 * p + 1] == c.rgb[p][1]);
      CHECK(d.rgba[4 * p + 2] == c.rgb[p][2]);
      CHECK(d.rgba[4 * p + 3] == 255);
    }
  }
  // Floats: a NaN shows white, and the finite differences scale without it.
  const golden::ImageF fe{3, 1, {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1}};
  const golden::ImageF fa{3, 1, {kNaN, 0, 0, 1, 0.5f, 0, 0, 1, 0.25f, 0, 0, 1}};
  const raster::Image8 fd = golden::diff_image(fe, fa);
  CHECK(std::vector<std::uint8_t>(fd.rgba.begin(), fd.rgba.end()) ==
        std::vector<std::uint8_t>{255, 255, 255, 255, 255, 255, 255, 255, 255, 255, 0, 255});
  CHECK_THROWS_WITH_AS(golden::diff_image(pattern8(2, 3), pattern8(3, 2)), doctest::Contains("expected 2x3, actual 3x2"),
                       std::invalid_argument);
}

TEST_CASE("side by side: expected | actual | diff for equal sizes, expected | actual on black for different sizes") {
  const raster::Image8 e = pattern8(4, 3, 1), a = pattern8(4, 3, 2);
  const raster::Image8 s = golden::side_by_side(e, a);
  REQUIRE(s.width == 12);
  REQUIRE(s.height == 3);
  const raster::Image8 d = golden::diff_image(e, a);
  auto px = [](const raster::Image8& im, int x, int y) {
    const std::size_t i = (static_cast<std::size_t>(y) * im.width + x) * 4;
    return std::array<std::uint8_t, 4>{im.rgba[i], im.rgba[i + 1], im.rgba[i + 2], im.rgba[i + 3]};
  };
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 4; ++x) {
      CHECK(px(s, x, y) == px(e, x, y));
      CHECK(px(s, x + 4, y) == px(a, x, y));
      CHECK(px(s, x + 8, y) == px(d, x, y));
    }
  const raster::Image8 small = pattern8(2, 5, 3);
  const raster::Image8 t = golden::side_by_side(e, small);
  REQUIRE(t.width == 6);
  REQUIRE(t.height == 5);
  CHECK(px(t, 0, 0) == px(e, 0, 0));
  CHECK(px(t, 3, 2) == px(e, 3, 2));
  CHECK(px(t, 0, 4) == std::array<std::uint8_t, 4>{0, 0, 0, 255});  // below expected
  CHECK(px(t, 5, 4) == px(small, 1, 4));
  // Float images are shown through to_srgb8.
  const golden::ImageF f = patternF(4, 3);
  const raster::Image8 sf = golden::side_by_side(f, f);
  CHECK(px(sf, 1, 1) == px(golden::to_srgb8(f), 1, 1));
  CHECK(px(sf, 9, 1) == std::array<std::uint8_t, 4>{0, 0, 0, 255});
}
