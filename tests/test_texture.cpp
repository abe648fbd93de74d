// Textures: mip chains, the decode tables, level of detail, wrap modes and filters against
// the OpenGL specification's formulas, and the packet form bit-identical to the scalar one.
#include <doctest/doctest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "image_helpers.h"
#include "softpbr/image/load.h"
#include "softpbr/image/write.h"
#include "softpbr/raster/color.h"
#include "softpbr/raster/pool.h"
#include "softpbr/raster/texture.h"
#include "texture_helpers.h"
#include "softpbr/simd/simd.h"

namespace raster = softpbr::raster;
namespace image = softpbr::image;
namespace simd = softpbr::simd;

namespace {

image::ImageF float_image(int w, int h, unsigned seed) {
  image::ImageF im;
  im.width = w;
  im.height = h;
  im.rgba.resize(static_cast<std::size_t>(w) * h * 4);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> d(0.0f, 4.0f);
  for (float& x : im.rgba) x = d(rng);
  return im;
}


// A w × 1 float texture whose texel i holds (i, 0, 0, 1): lookups say which texel they read.
raster::Texture index_texture(int w, int h = 1) {
  image::ImageF im;
  im.width = w;
  im.height = h;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) im.rgba.insert(im.rgba.end(), {float(x), float(y), 0.0f, 1.0f});
  return raster::Texture(im, {.mipmaps = false});
}

raster::Sampler nearest(raster::Wrap wrap) {
  raster::Sampler s;
  s.wrap_u = s.wrap_v = wrap;
  s.mag_filter = s.min_filter = raster::Filter::Nearest;
  s.mip_filter = raster::MipFilter::None;
  return s;
}

std::vector<double> level_means(const raster::Texture& t) {
  std::vector<double> means;
  for (int l = 0; l < t.level_count(); ++l) {
    const auto& lv = t.level(l);
    double sum[4] = {0, 0, 0, 0};
    for (int y = 0; y < lv.height; ++y)
      for (int x = 0; x < lv.width; ++x) {
        const glm::vec4 c = t.texel(l, x, y);
        for (int ch = 0; ch < 4; ++ch) sum[ch] += c[ch];
      }
    for (double s : sum) means.push_back(s / (double(lv.width) * lv.height));
  }
  return means;
}

}  // namespace

TEST_CASE("the mip chain has GL's level sizes, for non-powers of two and 1xN too") {
  CHECK(raster::mip_level_count(1, 1) == 1);
  CHECK(raster::mip_level_count(16, 16) == 5);
  CHECK(raster::mip_level_count(5, 3) == 3);
  CHECK(raster::mip_level_count(1, 7) == 3);
  CHECK(raster::mip_level_count(16384, 3) == 15);
  const raster::Texture t(float_image(5, 3, 1));
  REQUIRE(t.level_count() == 3);
  CHECK(t.level(1).width == 2);
  CHECK(t.level(1).height == 1);
  CHECK(t.level(2).width == 1);
  CHECK(t.level(2).height == 1);
  const raster::Texture tall(float_image(1, 7, 2));
  REQUIRE(tall.level_count() == 3);
  CHECK(tall.level(1).width == 1);
  CHECK(tall.level(1).height == 3);
  CHECK(tall.level(2).height == 1);
  CHECK(tall.level(2).offset == 7 + 3);
  const raster::Texture single(float_image(37, 21, 3), {.mipmaps = false});
  CHECK(single.level_count() == 1);
}

TEST_CASE("every mip level keeps the image's mean (odd sizes included)") {
  for (const std::pair<int, int>& size : {std::pair{64, 64}, {37, 21}, {1, 13}, {9, 1}, {3, 3}}) {
    const int w = size.first, h = size.second;  // not a structured binding: CAPTURE's lambda captures them
    CAPTURE(w);
    CAPTURE(h);
    const raster::Texture t(float_image(w, h, static_cast<unsigned>(w * 31 + h)));
    const auto means = level_means(t);
    for (int l = 1; l < t.level_count(); ++l)
      for (int ch = 0; ch < 4; ++ch) CHECK(means[l * 4 + ch] == doctest::Approx(means[ch]).epsilon(2e-6));
    // Quantized to 8 bits per level, a linear texture stays within a code of the mean,
    // and an sRGB one within a code's width of linear light.
    const raster::Texture lin(softpbr::test::random_image8(w, h, static_cast<unsigned>(w + h)), raster::ColorSpace::Linear);
    const raster::Texture srgb(softpbr::test::random_image8(w, h, static_cast<unsigned>(w + h)), raster::ColorSpace::Srgb);
    const auto lm = level_means(lin), sm = level_means(srgb);
    for (int l = 1; l < lin.level_count(); ++l)
      for (int ch = 0; ch < 4; ++ch) {
        CHECK(std::abs(lm[l * 4 + ch] - lm[ch]) <= 1.0 / 255.0 * l);
        CHECK(std::abs(sm[l * 4 + ch] - sm[ch]) <= (ch == 3 ? 1.0 / 255.0 : 0.02) * l);
      }
  }
}

TEST_CASE("sRGB mips are filtered in linear light") {
  // Black and white columns: the average in linear light is 0.5, which sRGB encodes as
  // code 188; averaging the codes would give 128 (too dark, the classic mistake).
  image::Image8 im;
  im.width = 2;
  im.height = 1;
  im.rgba = {0, 0, 0, 255, 255, 255, 255, 255};
  const raster::Texture t(im, raster::ColorSpace::Srgb);
  REQUIRE(t.level_count() == 2);
  CHECK(t.texels8()[8] == 188);  // level 1 starts after the 2 texels of level 0
  CHECK(t.texels8()[11] == 255);
  const raster::Texture lin(im, raster::ColorSpace::Linear);
  CHECK(lin.texels8()[8] == 128);
}

TEST_CASE("the sRGB decode table is exact for all 256 codes") {
  const float* table = raster::srgb8_decode_table();
  for (int k = 0; k < 256; ++k) {
    CAPTURE(k);
    const long double e = k / 255.0L;
    const long double ref = e <= 0.04045L ? e / 12.92L : std::pow((e + 0.055L) / 1.055L, 2.4L);
    CHECK(table[k] == static_cast<float>(ref));
    // The encoder inverts it exactly.
    CHECK(raster::linear_to_srgb8(table[k]) == k);
    CHECK(raster::unorm8_decode_table()[k] == static_cast<float>(k) / 255.0f);
  }
  CHECK(table[0] == 0.0f);
  CHECK(table[255] == 1.0f);
}

TEST_CASE("lod_log2 is accurate, exact at powers of two, and total") {
  for (int e = -140; e <= 127; ++e) CHECK(raster::lod_log2(std::ldexp(1.0f, e)) == static_cast<float>(e));
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> d(-30.0f, 30.0f);
  for (int i = 0; i < 20000; ++i) {
    const float x = std::exp2(d(rng));
    const double ref = std::log2(static_cast<double>(x));
    CHECK(std::abs(raster::lod_log2(x) - ref) <= 3e-7 * std::max(1.0, std::abs(ref)));
  }
  CHECK(raster::lod_log2(0.0f) == -INFINITY);
  CHECK(raster::lod_log2(INFINITY) == INFINITY);
  CHECK(std::isnan(raster::lod_log2(-1.0f)));
  CHECK(std::isnan(raster::lod_log2(NAN)));
}

TEST_CASE("level of detail follows the OpenGL formula, isotropic and anisotropic") {
  const raster::Texture t(float_image(256, 128, 4));
  raster::Sampler s;
  s.min_lod = -1000.0f;  // see the raw λ
  auto lod = [&](glm::vec2 dx, glm::vec2 dy) { return t.footprint(s, dx, dy).lod; };
  auto gl = [&](glm::vec2 dx, glm::vec2 dy) {  // λ = log₂ max(|dx|, |dy|) in texels, in double
    const double px = std::hypot(double(dx.x) * 256, double(dx.y) * 128);
    const double py = std::hypot(double(dy.x) * 256, double(dy.y) * 128);
    return std::log2(std::max(px, py));
  };
  // Minification by 4 along x: λ = 2 exactly.
  CHECK(lod({4.0f / 256, 0}, {0, 1.0f / 128}) == 2.0f);
  // Magnification: half a texel per pixel, λ = −1.
  CHECK(lod({0.5f / 256, 0}, {0, 0.5f / 128}) == -1.0f);
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> d(-0.2f, 0.2f);
  for (int i = 0; i < 1000; ++i) {
    const glm::vec2 dx(d(rng), d(rng)), dy(d(rng), d(rng));
    CHECK(lod(dx, dy) == doctest::Approx(gl(dx, dy)).epsilon(1e-5));
  }
  // Clamps and bias: λ' = λ + bias, then [min_lod, max_lod].
  s.lod_bias = 0.5f;
  CHECK(lod({4.0f / 256, 0}, {0, 1.0f / 128}) == 2.5f);
  CHECK(t.footprint(s, {4.0f / 256, 0}, {0, 1.0f / 128}, 1.0f).lod == 3.5f);
  s.max_lod = 3.0f;
  CHECK(lod({64.0f / 256, 0}, {0, 1.0f / 128}) == 3.0f);
  s = raster::Sampler{};
  CHECK(t.footprint(s, {0.5f / 256, 0}, {0, 0.5f / 128}).lod == 0.0f);  // min_lod 0
  CHECK(t.footprint(s, {0, 0}, {0, 0}).lod == 0.0f);                      // −∞ clamped
  CHECK(t.footprint(s, {NAN, INFINITY}, {0, 0}).lod == 0.0f);             // non-finite → 0
  CHECK(t.footprint(s, {1e30f, 1e30f}, {0, 0}).lod == s.max_lod);         // overflow → ∞ → max

  // Anisotropic: P_max = 8, P_min = 2 texels → N = 4 probes at λ = log₂(8/4) = 1.
  s.max_anisotropy = 16;
  auto fp = t.footprint(s, {8.0f / 256, 0}, {0, 2.0f / 128});
  CHECK(fp.probes == 4);
  CHECK(fp.lod == 1.0f);
  // A ratio of 2.5 takes ⌈2.5⌉ = 3 probes at λ = log₂(5/3).
  fp = t.footprint(s, {0, 5.0f / 128}, {2.0f / 256, 0});
  CHECK(fp.probes == 3);
  CHECK(fp.lod == doctest::Approx(std::log2(5.0 / 3.0)).epsilon(1e-6));
  // The limit: 64:1 with at most 16 probes → λ = log₂(64/16) = 2.
  fp = t.footprint(s, {64.0f / 256, 0}, {0, 1.0f / 128});
  CHECK(fp.probes == 16);
  CHECK(fp.lod == 2.0f);
  s.max_anisotropy = 2;
  fp = t.footprint(s, {64.0f / 256, 0}, {0, 1.0f / 128});
  CHECK(fp.probes == 2);
  CHECK(fp.lod == 5.0f);
  // A degenerate footprint (P_min = 0) takes the most probes.
  s.max_anisotropy = 8;
  CHECK(t.footprint(s, {8.0f / 256, 0}, {0, 0}).probes == 8);
  // Isotropic footprints take one.
  CHECK(t.footprint(s, {2.0f / 256, 0}, {0, 2.0f / 128}).probes == 1);
}

TEST_CASE("wrap modes read the texels the specification names at the borders") {
  const raster::Texture t = index_texture(4);
  auto texel_at = [&](raster::Wrap wrap, float u) { return t.sample_lod(nearest(wrap), {u, 0.5f}, 0.0f).r; };
  // u · 4 → texel floor(u · 4), then wrapped: hand-computed for a 4-texel row.
  struct Case {
    float u;
    float repeat, clamp, mirror;
  };
  const Case cases[] = {
      {0.125f, 0, 0, 0},    {0.875f, 3, 3, 3},   {-0.125f, 3, 0, 0},  {-0.375f, 2, 0, 1},
      {1.125f, 0, 3, 3},    {1.375f, 1, 3, 2},   {1.875f, 3, 3, 0},   {2.125f, 0, 3, 0},
      {-1.125f, 3, 0, 3},   {-1.875f, 0, 0, 0},  {0.999f, 3, 3, 3},   {1.0f, 0, 3, 3},
  };
  for (const Case& c : cases) {
    CAPTURE(c.u);
    CHECK(texel_at(raster::Wrap::Repeat, c.u) == c.repeat);
    CHECK(texel_at(raster::Wrap::ClampToEdge, c.u) == c.clamp);
    CHECK(texel_at(raster::Wrap::MirroredRepeat, c.u) == c.mirror);
  }
  // Linear filtering at the left edge: centres at (i + ½)/4; u = 0 lies halfway between
  // texel −1 and texel 0.
  raster::Sampler lin = nearest(raster::Wrap::Repeat);
  lin.mag_filter = raster::Filter::Linear;
  CHECK(t.sample_lod(lin, {0.0f, 0.5f}, 0.0f).r == 1.5f);  // (3 + 0) / 2
  lin.wrap_u = raster::Wrap::ClampToEdge;
  CHECK(t.sample_lod(lin, {0.0f, 0.5f}, 0.0f).r == 0.0f);
  lin.wrap_u = raster::Wrap::MirroredRepeat;
  CHECK(t.sample_lod(lin, {0.0f, 0.5f}, 0.0f).r == 0.0f);
  // At a texel centre linear filtering returns the texel; a quarter past, the blend.
  lin.wrap_u = raster::Wrap::Repeat;
  CHECK(t.sample_lod(lin, {2.5f / 4, 0.5f}, 0.0f).r == 2.0f);
  CHECK(t.sample_lod(lin, {2.75f / 4, 0.5f}, 0.0f).r == 2.25f);
  // v wraps independently of u: rows top down, v = 0 at the top.
  const raster::Texture rows = index_texture(1, 4);
  raster::Sampler sv = nearest(raster::Wrap::ClampToEdge);
  sv.wrap_v = raster::Wrap::Repeat;
  CHECK(rows.sample_lod(sv, {-5.0f, 0.1f}, 0.0f).g == 0.0f);
  CHECK(rows.sample_lod(sv, {-5.0f, 0.9f}, 0.0f).g == 3.0f);
  CHECK(rows.sample_lod(sv, {-5.0f, -0.1f}, 0.0f).g == 3.0f);
  // Non-finite and huge coordinates read a texel, never out of bounds.
  for (float u : {NAN, INFINITY, -INFINITY, 1e30f, -1e30f, 65536.5f}) {
    for (raster::Wrap w : {raster::Wrap::Repeat, raster::Wrap::ClampToEdge, raster::Wrap::MirroredRepeat}) {
      const float x = texel_at(w, u);
      CHECK(x >= 0.0f);
      CHECK(x <= 3.0f);
    }
  }
}

TEST_CASE("mip filters: nearest level, linear between levels, none") {
  // A 4 × 4 texture of 1s with level 1 = 1 and level 2 = 1 would hide the blend: use a
  // texture whose levels differ — a 2 × 2 of (0, 4 ; 4, 0): level 0 mean 2, level 1 = 2.
  image::ImageF im;
  im.width = im.height = 2;
  im.rgba = {0, 0, 0, 1, 4, 4, 4, 1, 4, 4, 4, 1, 0, 0, 0, 1};
  const raster::Texture t(im);
  raster::Sampler s;
  s.mag_filter = s.min_filter = raster::Filter::Nearest;
  s.mip_filter = raster::MipFilter::Linear;
  const glm::vec2 at(0.25f, 0.25f);  // texel (0, 0) = 0 at level 0
  CHECK(t.sample_lod(s, at, 0.0f).r == 0.0f);   // λ ≤ 0: magnification, level 0
  CHECK(t.sample_lod(s, at, 0.25f).r == 0.5f);  // ¾ · 0 + ¼ · 2
  CHECK(t.sample_lod(s, at, 1.0f).r == 2.0f);
  CHECK(t.sample_lod(s, at, 7.0f).r == 2.0f);   // past the last level
  s.mip_filter = raster::MipFilter::Nearest;
  CHECK(t.sample_lod(s, at, 0.5f).r == 0.0f);   // λ ≤ ½ → level 0
  CHECK(t.sample_lod(s, at, 0.51f).r == 2.0f);  // ⌈λ + ½⌉ − 1 = 1
  s.mip_filter = raster::MipFilter::None;
  CHECK(t.sample_lod(s, at, 3.0f).r == 0.0f);
  // max_lod caps the level.
  s.mip_filter = raster::MipFilter::Linear;
  s.max_lod = 0.25f;
  CHECK(t.sample_lod(s, at, 5.0f).r == 0.5f);
  // NaN λ reads as 0.
  CHECK(t.sample_lod(s, at, NAN).r == 0.0f);
}

TEST_CASE("anisotropic lookups average probes along the major axis") {
  // A 64 × 64 texture of vertical stripes (texel x holds x): minified 8:1 along u and
  // magnified along v, 8 probes at λ = 0 average the row exactly as the probe positions say.
  image::ImageF im;
  im.width = im.height = 64;
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) im.rgba.insert(im.rgba.end(), {float(x), 0.0f, 0.0f, 1.0f});
  const raster::Texture t(im);
  raster::Sampler s;
  s.mag_filter = s.min_filter = raster::Filter::Nearest;
  s.max_anisotropy = 8;
  const glm::vec2 dx(8.0f / 64, 0.0f), dy(0.0f, 1.0f / 64);
  const glm::vec2 uv(32.0f / 64, 0.5f);
  REQUIRE(t.footprint(s, dx, dy).probes == 8);
  REQUIRE(t.footprint(s, dx, dy).lod == 0.0f);
  double expected = 0.0;
  for (int i = 1; i <= 8; ++i) expected += std::floor(32.0 + 8.0 * (i / 9.0 - 0.5));
  CHECK(t.sample(s, uv, dx, dy).r == doctest::Approx(expected / 8).epsilon(1e-6));
  // Isotropic, the same footprint reads level 3 (λ = 3): the mean of 8 columns around.
  s.max_anisotropy = 1;
  CHECK(t.footprint(s, dx, dy).lod == 3.0f);
}

TEST_CASE("the packet form returns the scalar form's bits at 4, 8 and 16 lanes") {
  raster::Sampler samplers[4];
  samplers[1].max_anisotropy = 16;
  samplers[2].wrap_u = raster::Wrap::MirroredRepeat;
  samplers[2].wrap_v = raster::Wrap::ClampToEdge;
  samplers[2].mip_filter = raster::MipFilter::Nearest;
  samplers[3].mag_filter = samplers[3].min_filter = raster::Filter::Nearest;
  samplers[3].lod_bias = -0.7f;
  const raster::Texture textures[] = {raster::Texture(softpbr::test::random_image8(37, 64, 5), raster::ColorSpace::Srgb),
                                      raster::Texture(float_image(128, 9, 6))};
  std::mt19937 rng(13);
  std::uniform_real_distribution<float> uv(-2.0f, 3.0f), du(-0.3f, 0.3f), lod(-2.0f, 9.0f);
  auto check_width = [&]<int N>() {
    using F = simd::Vec<N>;
    for (const raster::Texture& t : textures)
      for (const raster::Sampler& s : samplers)
        for (int rep = 0; rep < 50; ++rep) {
          float a[7][N];
          for (auto& row : a)
            for (float& x : row) x = &row == &a[0] || &row == &a[1] ? uv(rng) : du(rng);
          for (float& x : a[6]) x = lod(rng);
          const raster::Color<F> c = raster::sample(t, s, F::load(a[0]), F::load(a[1]), F::load(a[2]), F::load(a[3]),
                                                     F::load(a[4]), F::load(a[5]));
          const raster::Color<F> cl = raster::sample_lod(t, s, F::load(a[0]), F::load(a[1]), F::load(a[6]));
          for (int i = 0; i < N; ++i) {
            const raster::Color<float> one = raster::sample<float>(t, s, a[0][i], a[1][i], a[2][i], a[3][i], a[4][i], a[5][i]);
            CHECK(std::bit_cast<std::uint32_t>(c.r[i]) == std::bit_cast<std::uint32_t>(one.r));
            CHECK(std::bit_cast<std::uint32_t>(c.g[i]) == std::bit_cast<std::uint32_t>(one.g));
            CHECK(std::bit_cast<std::uint32_t>(c.b[i]) == std::bit_cast<std::uint32_t>(one.b));
            CHECK(std::bit_cast<std::uint32_t>(c.a[i]) == std::bit_cast<std::uint32_t>(one.a));
            const raster::Color<float> ol = raster::sample_lod<float>(t, s, a[0][i], a[1][i], a[6][i]);
            CHECK(std::bit_cast<std::uint32_t>(cl.r[i]) == std::bit_cast<std::uint32_t>(ol.r));
            CHECK(std::bit_cast<std::uint32_t>(cl.a[i]) == std::bit_cast<std::uint32_t>(ol.a));
          }
        }
  };
  check_width.operator()<4>();
  check_width.operator()<8>();
  check_width.operator()<16>();
}

TEST_CASE("a mip chain built on a pool has the same bits as one built on one thread") {
  raster::ThreadPool pool(4);
  const image::Image8 im = softpbr::test::random_image8(1031, 517, 9);  // big enough to be split
  const raster::Texture a(im, raster::ColorSpace::Srgb);
  const raster::Texture b(im, raster::ColorSpace::Srgb, {}, &pool);
  CHECK(a.level_count() == b.level_count());
  CHECK(std::equal(a.texels8().begin(), a.texels8().end(), b.texels8().begin(), b.texels8().end()));
  const image::ImageF fim = float_image(700, 300, 10);
  const raster::Texture fa(fim), fb(fim, {}, &pool);
  CHECK(std::equal(fa.texels_f().begin(), fa.texels_f().end(), fb.texels_f().begin(), fb.texels_f().end()));
}

namespace {

// The mip filter as docs/design.md states it and texture.cpp's general loop computes it:
// destination texel i of an axis from n to m = max(1, ⌊n/2⌋) texels takes source texels
// ⌊i·n/m⌋ … with weights overlap / n (in units of 1/m), vertical taps first, then
// horizontal, every sum starting at 0 and added in tap order. `fetch(x, y, c)` reads the
// previous level decoded, `store(x, y, c)` writes one texel.
struct RefTaps {
  int first = 0;
  std::vector<float> weight;
};
std::vector<RefTaps> ref_taps(int n, int m) {
  std::vector<RefTaps> taps(static_cast<std::size_t>(m));
  for (int i = 0; i < m; ++i) {
    const long long lo = static_cast<long long>(i) * n, hi = lo + n;
    RefTaps& t = taps[static_cast<std::size_t>(i)];
    t.first = static_cast<int>(lo / m);
    for (long long j = t.first; j * m < hi; ++j)
      t.weight.push_back(static_cast<float>(std::min((j + 1) * m, hi) - std::max(j * m, lo)) / static_cast<float>(n));
  }
  return taps;
}
template <class Fetch, class Store>
void ref_level(int sw, int sh, int dw, int dh, const Fetch& fetch, const Store& store) {
  const auto fx = ref_taps(sw, dw), fy = ref_taps(sh, dh);
  std::vector<float> row(static_cast<std::size_t>(sw) * 4);
  for (int y = 0; y < dh; ++y) {
    const RefTaps& ty = fy[static_cast<std::size_t>(y)];
    for (int x = 0; x < sw; ++x) {
      float acc[4] = {0.0f, 0.0f, 0.0f, 0.0f};
      for (std::size_t k = 0; k < ty.weight.size(); ++k) {
        float c[4];
        fetch(x, ty.first + static_cast<int>(k), c);
        for (int ch = 0; ch < 4; ++ch) acc[ch] += c[ch] * ty.weight[k];
      }
      std::copy(acc, acc + 4, row.begin() + 4 * x);
    }
    for (int x = 0; x < dw; ++x) {
      const RefTaps& tx = fx[static_cast<std::size_t>(x)];
      float acc[4] = {0.0f, 0.0f, 0.0f, 0.0f};
      for (std::size_t k = 0; k < tx.weight.size(); ++k)
        for (int ch = 0; ch < 4; ++ch) acc[ch] += row[4 * (static_cast<std::size_t>(tx.first) + k) + static_cast<std::size_t>(ch)] * tx.weight[k];
      store(x, y, acc);
    }
  }
}

}  // namespace

TEST_CASE("linear_to_srgb8 counts the thresholds at or below the value, as a binary search does") {
  const auto& t = raster::srgb8_thresholds();
  auto reference = [&](float v) -> int {
    if (!(v >= t[0])) return 0;
    return static_cast<int>(std::upper_bound(t.begin(), t.end(), v) - t.begin());
  };
  std::size_t checked = 0, mismatches = 0;
  auto check_bits = [&](std::uint32_t bits) {
    const float v = std::bit_cast<float>(bits);
    ++checked;
    if (raster::linear_to_srgb8(v) != reference(v)) ++mismatches;
  };
  // Around every threshold, around every 16-bit key boundary below 1, and a stride over
  // all floats in [0, 1.0f], negatives, infinities and NaNs.
  for (float x : t)
    for (int d = -512; d <= 512; ++d) check_bits(std::bit_cast<std::uint32_t>(x) + static_cast<std::uint32_t>(d));
  for (std::uint32_t k = 0; k <= 0x3f80u; ++k)
    for (std::uint32_t d = 0; d < 4; ++d) {
      check_bits((k << 16) + d);
      if (k > 0) check_bits((k << 16) - 1 - d);
    }
  for (std::uint32_t bits = 0; bits <= 0x3f800000u; bits += 4093) check_bits(bits);
  for (std::uint32_t bits : {0x3f800000u, 0x3f800001u, 0x7f7fffffu, 0x7f800000u, 0x7fc00000u, 0x80000000u, 0xbf800000u,
                             0xff800000u, 0xffc00000u, 0x00000001u})
    check_bits(bits);
  CHECK(checked > 600000);
  CHECK(mismatches == 0);
}

TEST_CASE("mip levels are the general box filter's bits, even sizes (the 2x2 fast path) and odd ones") {
  const float* srgb = raster::srgb8_decode_table();
  const float* unorm = raster::unorm8_decode_table();
  raster::ThreadPool pool(2);
  // Even all the way down, even then odd (12 → 6 → 3), odd, a 1-high strip, and a texture
  // big enough for the pool to split the rows.
  const int sizes[][2] = {{64, 32}, {2, 2}, {12, 20}, {7, 5}, {16, 1}, {1, 8}, {6, 14}, {512, 256}};
  for (const auto& size : sizes) {
    for (raster::ColorSpace space : {raster::ColorSpace::Srgb, raster::ColorSpace::Linear}) {
      CAPTURE(size[0]);
      CAPTURE(size[1]);
      const image::Image8 im = softpbr::test::random_image8(size[0], size[1], 21u + static_cast<unsigned>(size[0]));
      const raster::Texture tex(im, space, {}, size[0] >= 512 ? &pool : nullptr);
      std::vector<std::uint8_t> expect(tex.texels8().size());
      std::copy(im.rgba.begin(), im.rgba.end(), expect.begin());
      const float* rgb = space == raster::ColorSpace::Srgb ? srgb : unorm;
      for (int l = 1; l < tex.level_count(); ++l) {
        const auto& src = tex.level(l - 1);
        const auto& dst = tex.level(l);
        const std::uint8_t* in = expect.data() + src.offset * 4;
        std::uint8_t* out = expect.data() + dst.offset * 4;
        ref_level(
            src.width, src.height, dst.width, dst.height,
            [&](int x, int y, float c[4]) {
              const std::uint8_t* p = in + (static_cast<std::size_t>(y) * src.width + x) * 4;
              c[0] = rgb[p[0]];
              c[1] = rgb[p[1]];
              c[2] = rgb[p[2]];
              c[3] = unorm[p[3]];
            },
            [&](int x, int y, const float c[4]) {
              std::uint8_t* p = out + (static_cast<std::size_t>(y) * dst.width + x) * 4;
              for (int ch = 0; ch < 3; ++ch)
                p[ch] = space == raster::ColorSpace::Srgb ? raster::linear_to_srgb8(c[ch]) : raster::unorm8(c[ch]);
              p[3] = raster::unorm8(c[3]);
            });
      }
      CHECK(std::equal(expect.begin(), expect.end(), tex.texels8().begin(), tex.texels8().end()));
    }
    // Float textures, with negative values and zeros of both signs (0 + a·½ + b·½ keeps
    // the general loop's +0 for −0 inputs).
    image::ImageF fim = float_image(size[0], size[1], 33u + static_cast<unsigned>(size[1]));
    for (int y = 0; y < fim.height; ++y)
      for (int x = 0; x < fim.width; ++x) {
        float* p = &fim.rgba[(static_cast<std::size_t>(y) * fim.width + x) * 4];
        if ((x / 2 + y / 2) % 3 == 0) p[0] = -0.0f;  // whole 2×2 blocks of −0
        p[1] = -p[1];
      }
    const raster::Texture ftex(fim, {}, size[0] >= 512 ? &pool : nullptr);
    std::vector<float> expect(ftex.texels_f().size());
    std::copy(fim.rgba.begin(), fim.rgba.end(), expect.begin());
    for (int l = 1; l < ftex.level_count(); ++l) {
      const auto& src = ftex.level(l - 1);
      const auto& dst = ftex.level(l);
      const float* in = expect.data() + src.offset * 4;
      float* out = expect.data() + dst.offset * 4;
      ref_level(
          src.width, src.height, dst.width, dst.height,
          [&](int x, int y, float c[4]) {
            const float* p = in + (static_cast<std::size_t>(y) * src.width + x) * 4;
            std::copy(p, p + 4, c);
          },
          [&](int x, int y, const float c[4]) { std::copy(c, c + 4, out + (static_cast<std::size_t>(y) * dst.width + x) * 4); });
    }
    bool same = expect.size() == ftex.texels_f().size();
    for (std::size_t i = 0; same && i < expect.size(); ++i)
      same = std::bit_cast<std::uint32_t>(expect[i]) == std::bit_cast<std::uint32_t>(ftex.texels_f()[i]);
    CHECK(same);
  }
}

TEST_CASE("textures and samplers refuse what they cannot hold") {
  image::Image8 empty;
  CHECK_THROWS_AS(raster::Texture(empty, raster::ColorSpace::Srgb), std::invalid_argument);
  image::ImageF wrong;
  wrong.width = 2;
  wrong.height = 2;
  wrong.rgba.resize(15);
  CHECK_THROWS_AS(raster::Texture{wrong}, std::invalid_argument);
  image::ImageF nan = float_image(2, 2, 1);
  nan.rgba[5] = NAN;
  CHECK_THROWS_AS(raster::Texture{nan}, std::invalid_argument);
  image::ImageF wide;
  wide.width = raster::kMaxTextureSide + 1;
  wide.height = 1;
  wide.rgba.resize(static_cast<std::size_t>(wide.width) * 4);
  CHECK_THROWS_AS(raster::Texture{wide}, std::invalid_argument);
  raster::Sampler s;
  CHECK_NOTHROW(raster::validate(s));
  s.max_anisotropy = 17;
  CHECK_THROWS_AS(raster::validate(s), std::invalid_argument);
  s = {};
  s.max_anisotropy = 0;
  CHECK_THROWS_AS(raster::validate(s), std::invalid_argument);
  s = {};
  s.min_lod = 2;
  s.max_lod = 1;
  CHECK_THROWS_AS(raster::validate(s), std::invalid_argument);
  s = {};
  s.lod_bias = NAN;
  CHECK_THROWS_AS(raster::validate(s), std::invalid_argument);
  s = {};
  s.wrap_u = static_cast<raster::Wrap>(7);
  CHECK_THROWS_AS(raster::validate(s), std::invalid_argument);
}

TEST_CASE("a texture made from a moved image decoded with room for its mip chain keeps the buffer, with the same texels") {
  // rgba8_chain_bytes is what the texture's levels take.
  for (const auto& size : std::vector<std::pair<int, int>>{{1, 1}, {1, 37}, {64, 64}, {1031, 517}, {3, 2}}) {
    const int w = size.first, h = size.second;  // not a structured binding: CAPTURE's lambda takes it (Clang 14)
    CAPTURE(w);
    CAPTURE(h);
    const raster::Texture t(softpbr::test::random_image8(w, h, 3), raster::ColorSpace::Linear);
    CHECK(raster::Texture::rgba8_chain_bytes(w, h) == t.texel_bytes());
  }
  CHECK(raster::Texture::rgba8_chain_bytes(0, 4) == 0);
  CHECK(raster::Texture::rgba8_chain_bytes(4, raster::kMaxTextureSide + 1) == 0);

  raster::ThreadPool pool(2);
  const image::Image8 original = image_test::smooth8(1031, 517);
  for (const auto& file : std::vector<std::pair<std::string, std::vector<std::uint8_t>>>{
           {"png", image::encode_png(original, "png")}, {"jpeg", image_test::jpeg_of(original, 3, 90)}}) {
    const std::string& format = file.first;
    const std::vector<std::uint8_t>& encoded = file.second;
    CAPTURE(format);
    image::Image8 roomy = image::load_image8(encoded, format, {}, &raster::Texture::rgba8_chain_bytes);
    const image::Image8 plain = image::load_image8(encoded, format);
    CHECK(roomy.rgba == plain.rgba);
    CHECK(roomy.rgba.capacity() >= raster::Texture::rgba8_chain_bytes(1031, 517));
    for (const raster::ColorSpace space : {raster::ColorSpace::Srgb, raster::ColorSpace::Linear}) {
      image::Image8 moved = roomy;
      moved.rgba.reserve(roomy.rgba.capacity());
      const std::uint8_t* buffer = moved.rgba.data();
      const raster::Texture taken(std::move(moved), space, {}, &pool);
      const raster::Texture copied(plain, space);
      CHECK(taken.texels8().data() == buffer);  // no copy, no second buffer
      CHECK(std::ranges::equal(taken.texels8(), copied.texels8()));
      CHECK(moved.rgba.empty());
      CHECK(moved.width == 0);
    }
    // Without room the texels move to a new buffer: the same texels.
    image::Image8 tight = plain;
    tight.rgba.shrink_to_fit();
    const raster::Texture moved_tight(std::move(tight), raster::ColorSpace::Srgb);
    CHECK(std::ranges::equal(moved_tight.texels8(), raster::Texture(plain, raster::ColorSpace::Srgb).texels8()));
    // No mip chain: the base level only.
    image::Image8 base_only = plain;
    const raster::Texture flat(std::move(base_only), raster::ColorSpace::Linear, {.mipmaps = false});
    CHECK(flat.level_count() == 1);
    CHECK(std::ranges::equal(flat.texels8(), plain.rgba));
  }
  // A wrong-sized image is refused as by the view constructor.
  image::Image8 bad{4, 4, std::vector<std::uint8_t>(10)};
  CHECK_THROWS_AS(raster::Texture(std::move(bad), raster::ColorSpace::Srgb), std::invalid_argument);
}
