// The texture lane kernels (raster/src/texture-inl.h, run by Texture::sample_batch on
// CPUs with AVX2 (8 lanes) or AVX-512 (16 lanes) for 8-bit textures with power-of-two sides
// through repeat, trilinear samplers) against the scalar lookup, bit for bit, on random
// and hostile inputs: each kernel the CPU runs (AVX-512 with and without VBMI's byte
// permutes), every batch size from 1 to 17 (partial groups of 8 and 16), anisotropy 1 to
// 16, LOD biases and limits that put lanes in magnification, between levels and on the
// last level, and coordinates and derivatives that are zero, subnormal, huge, infinite
// or NaN, and groups of ordinary lanes only (the kernels' fast paths); lookups through a
// BoundTexture as well. Elsewhere (no AVX2, other textures or
// samplers) sample_batch runs the scalar code and this passes trivially.
#include <doctest/doctest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <utility>
#include <vector>

#include "softpbr/raster/texture.h"
#include "texture_helpers.h"

namespace raster = softpbr::raster;
namespace image = softpbr::image;

namespace {


// Mostly ordinary values of magnitude up to `scale`, sometimes the special ones (never
// with `ordinary`: a whole group of such lanes takes the kernels' fast paths, which skip
// the special cases' selects).
float value(std::mt19937& rng, float scale, bool ordinary = false) {
  constexpr float inf = std::numeric_limits<float>::infinity();
  switch (ordinary ? 47 : rng() % 48) {
    case 0: return std::numeric_limits<float>::quiet_NaN();
    case 1: return inf;
    case 2: return -inf;
    case 3: return 0.0f;
    case 4: return -0.0f;
    case 5: return 3e38f;
    case 6: return -7e4f;
    case 7: return std::numeric_limits<float>::denorm_min();
    case 8: return static_cast<float>(static_cast<int>(rng() % 64) - 32) / 16.0f;  // on texel edges
    default: return std::uniform_real_distribution<float>(-scale, scale)(rng);
  }
}

}  // namespace

TEST_CASE("the 8- and 16-lane texture kernels return the scalar lookup's bits") {
  using softpbr::simd::Isa;
  // The AVX-512 kernel twice where the CPU has VBMI: its plain copy and its VBMI copy.
  const std::pair<Isa, bool> kernels[] = {
      {Isa::Baseline, false}, {Isa::Avx2, false}, {Isa::Avx512, false}, {Isa::Avx512, true}};
  for (const auto& kernel : kernels) {
    const Isa isa = kernel.first;  // not a structured binding: CAPTURE's lambda (Clang 15)
    const bool vbmi = kernel.second;
    if (!softpbr::simd::supported(isa) || (vbmi && !softpbr::simd::cpu_has_avx512_vbmi())) continue;
    CAPTURE(static_cast<int>(isa));
    CAPTURE(vbmi);
    raster::detail::allow_texture_vbmi(vbmi);
    const raster::Texture textures[] = {
        raster::Texture(softpbr::test::random_image8(256, 256, 1), raster::ColorSpace::Srgb),
        raster::Texture(softpbr::test::random_image8(64, 16, 2), raster::ColorSpace::Linear),
        raster::Texture(softpbr::test::random_image8(1, 128, 3), raster::ColorSpace::Srgb),
        raster::Texture(softpbr::test::random_image8(1, 1, 4), raster::ColorSpace::Srgb),
        raster::Texture(softpbr::test::random_image8(32, 32, 5), raster::ColorSpace::Srgb, {.mipmaps = false}),
    };
    std::mt19937 rng(21);
    const int anisotropies[] = {1, 2, 5, 16};
    const float derivative_scales[] = {1e-4f, 4e-3f, 0.05f, 2.0f};
    long mismatches = 0, lookups = 0;
    for (const raster::Texture& t : textures)
      for (int rep = 0; rep < 400; ++rep) {
        raster::Sampler s;  // repeat, trilinear
        s.max_anisotropy = anisotropies[rep % 4];
        if (rep % 5 == 1) s.lod_bias = -1.5f;
        if (rep % 5 == 2) s.lod_bias = 2.25f;
        if (rep % 7 == 3) s.min_lod = 1.0f;
        if (rep % 7 == 4) s.max_lod = 2.5f;
        const float scale = derivative_scales[(rep / 4) % 4];
        constexpr int kMax = 17;
        const bool ordinary = rep % 3 == 0;
        std::vector<float> in[6], out[4], bound_out[4];
        for (auto& v : in) v.resize(kMax);
        for (auto& v : out) v.resize(kMax);
        for (auto& v : bound_out) v.resize(kMax);
        for (int i = 0; i < kMax; ++i) {
          in[0][i] = value(rng, 3.0f, ordinary);
          in[1][i] = value(rng, 3.0f, ordinary);
          for (int k = 2; k < 6; ++k) in[k][i] = value(rng, scale, ordinary);
          if (rng() % 3 == 0) {  // an anisotropic footprint along u
            in[3][i] = in[2][i] * 0.01f;
            in[4][i] = in[2][i] * 0.02f;
            in[5][i] = in[2][i] * 0.125f;
          }
        }
        const int n = ordinary && rep % 2 == 0 ? 16 : 1 + rep % kMax;  // whole groups of ordinary lanes
        t.sample_batch(s, n,
                       {in[0].data(), in[1].data(), in[2].data(), in[3].data(), in[4].data(), in[5].data(), nullptr,
                        out[0].data(), out[1].data(), out[2].data(), out[3].data()},
                       isa);
        // The same through the texture and sampler bound once (a shader's per-draw binding).
        raster::BoundTexture(t, s, isa)
            .sample_batch(n, {in[0].data(), in[1].data(), in[2].data(), in[3].data(), in[4].data(), in[5].data(),
                              nullptr, bound_out[0].data(), bound_out[1].data(), bound_out[2].data(),
                              bound_out[3].data()});
        for (int i = 0; i < n; ++i) {
          const glm::vec4 one = t.sample(s, {in[0][i], in[1][i]}, {in[2][i], in[3][i]}, {in[4][i], in[5][i]});
          ++lookups;
          for (int ch = 0; ch < 4; ++ch)
            if (std::bit_cast<std::uint32_t>(out[ch][i]) != std::bit_cast<std::uint32_t>(one[ch]) ||
                std::bit_cast<std::uint32_t>(bound_out[ch][i]) != std::bit_cast<std::uint32_t>(one[ch])) {
              ++mismatches;
              break;
            }
        }
      }
    CHECK(lookups > 10000);
    CHECK(mismatches == 0);
  }
  raster::detail::allow_texture_vbmi(true);
}

TEST_CASE("packets of a surface (8×2 and 4×4 pixels) get the scalar lookup's bits") {
  // The lanes of a shader's packet: a patch of pixels whose UVs are an affine map of the
  // pixel, at scales from magnification to a few levels down, rotated and sheared, at
  // random places (wrap seams and the levels' last rows and columns included), asking for
  // the channel sets the textured shader asks for (each has its own kernel; rgb decodes
  // four texel vectors together with VBMI). The random lanes above seldom make whole
  // groups that read two levels with every lane; these mostly do.
  using softpbr::simd::Isa;
  const std::pair<Isa, bool> kernels[] = {{Isa::Avx2, false}, {Isa::Avx512, false}, {Isa::Avx512, true}};
  const raster::Texture textures[] = {
      raster::Texture(softpbr::test::random_image8(256, 256, 11), raster::ColorSpace::Srgb),
      raster::Texture(softpbr::test::random_image8(64, 16, 12), raster::ColorSpace::Linear),
      raster::Texture(softpbr::test::random_image8(16, 4, 13), raster::ColorSpace::Srgb),  // levels down to 1×1
      raster::Texture(softpbr::test::random_image8(32, 128, 14), raster::ColorSpace::Srgb),
  };
  for (const auto& kernel : kernels) {
    const Isa isa = kernel.first;
    const bool vbmi = kernel.second;
    if (!softpbr::simd::supported(isa) || (vbmi && !softpbr::simd::cpu_has_avx512_vbmi())) continue;
    CAPTURE(static_cast<int>(isa));
    CAPTURE(vbmi);
    raster::detail::allow_texture_vbmi(vbmi);
    std::mt19937 rng(33);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    long mismatches = 0, lookups = 0;
    for (const raster::Texture& t : textures) {
      const float w = static_cast<float>(t.width()), h = static_cast<float>(t.height());
      for (int rep = 0; rep < 3000; ++rep) {
        raster::Sampler s;  // repeat, trilinear
        s.max_anisotropy = rep % 5 == 4 ? 4 : 1;
        // Texels a pixel at level 0: 2^-1.5 … 2^5.5; a rotation, a little shear and stretch.
        const float scale = std::exp2(unit(rng) * 7.0f - 1.5f);
        const float angle = rep % 3 == 0 ? 0.0f : unit(rng) * 6.2831853f;
        const float stretch = rep % 4 == 0 ? 1.0f : 0.7f + 0.6f * unit(rng);
        const float shear = rep % 4 == 1 ? 0.3f * (unit(rng) - 0.5f) : 0.0f;
        const float cs = std::cos(angle) * scale, sn = std::sin(angle) * scale;
        const float dudx = cs / w, dvdx = sn * stretch / h;
        const float dudy = (shear * cs - sn) / w, dvdy = cs * stretch / h;
        // Anywhere, or just before a level's last column or row (where neighbours wrap).
        float u0 = unit(rng) * 4.0f - 2.0f, v0 = unit(rng) * 4.0f - 2.0f;
        if (rep % 6 == 2) u0 = 1.0f - (1.0f + 14.0f * unit(rng)) * scale / w;
        if (rep % 6 == 3) v0 = 1.0f - (1.0f + 4.0f * unit(rng)) * scale / h;
        const bool square = rep % 2 == 0;  // 4×4 pixels, else 8×2
        float in[6][16], out[4][16];
        for (int i = 0; i < 16; ++i) {
          const float x = static_cast<float>(square ? i % 4 : i % 8), y = static_cast<float>(square ? i / 4 : i / 8);
          in[0][i] = u0 + dudx * x + dudy * y;
          in[1][i] = v0 + dvdx * x + dvdy * y;
          in[2][i] = dudx, in[3][i] = dvdx, in[4][i] = dudy, in[5][i] = dvdy;
        }
        constexpr unsigned kSets[] = {raster::Texture::kRgba, raster::Texture::kRgb,
                                      raster::Texture::kGreen | raster::Texture::kBlue, raster::Texture::kRed};
        const unsigned channels = kSets[(rep / 2) % 4];
        raster::BoundTexture(t, s, isa)
            .sample_batch(16,
                          {in[0], in[1], in[2], in[3], in[4], in[5], nullptr, out[0], out[1], out[2], out[3], channels});
        for (int i = 0; i < 16; ++i) {
          const glm::vec4 one = t.sample(s, {in[0][i], in[1][i]}, {in[2][i], in[3][i]}, {in[4][i], in[5][i]});
          ++lookups;
          for (int ch = 0; ch < 4; ++ch)
            if ((channels >> ch & 1) && std::bit_cast<std::uint32_t>(out[ch][i]) != std::bit_cast<std::uint32_t>(one[ch])) {
              ++mismatches;
              break;
            }
        }
      }
    }
    CHECK(lookups == 4 * 3000 * 16);
    CHECK(mismatches == 0);
  }
  raster::detail::allow_texture_vbmi(true);
}

TEST_CASE("a batch that asks for some channels gets them with the bits of a full lookup") {
  const raster::Texture t(softpbr::test::random_image8(128, 64, 7), raster::ColorSpace::Srgb);
  std::mt19937 rng(5);
  constexpr int kN = 19;  // full groups of 8 or 16 lanes and a partial one
  std::vector<float> in[6], full[4], part[4];
  for (auto& v : in) v.resize(kN);
  for (int i = 0; i < kN; ++i) {
    in[0][i] = value(rng, 3.0f);
    in[1][i] = value(rng, 3.0f);
    for (int k = 2; k < 6; ++k) in[k][i] = value(rng, 0.02f);
  }
  raster::Sampler s;  // repeat, trilinear
  s.max_anisotropy = 4;
  auto run = [&](std::vector<float>* out, unsigned channels) {
    for (int c = 0; c < 4; ++c) out[c].assign(kN, -1.0f);
    t.sample_batch(s, kN,
                   {in[0].data(), in[1].data(), in[2].data(), in[3].data(), in[4].data(), in[5].data(), nullptr,
                    out[0].data(), out[1].data(), out[2].data(), out[3].data(), channels});
  };
  for (const bool vbmi : {false, true}) {  // the AVX-512 kernel's two copies, on a VBMI CPU
    CAPTURE(vbmi);
    raster::detail::allow_texture_vbmi(vbmi);
    run(full, raster::Texture::kRgba);
    for (const unsigned channels : {0x7u, 0x6u, 0x1u, 0x5u, 0x8u, 0xFu}) {
      run(part, channels);
      CAPTURE(channels);
      int wrong = 0;
      for (int c = 0; c < 4; ++c)
        if (channels >> c & 1)
          for (int i = 0; i < kN; ++i)
            wrong += std::bit_cast<std::uint32_t>(part[c][i]) != std::bit_cast<std::uint32_t>(full[c][i]);
      CHECK(wrong == 0);
    }
  }
  // The packet form returns the channels asked for and 0 for the others.
  using V8 = softpbr::simd::Vec<8>;
  const raster::Color<V8> c = raster::sample(t, s, V8::load(in[0].data()), V8::load(in[1].data()),
                                             V8::load(in[2].data()), V8::load(in[3].data()), V8::load(in[4].data()),
                                             V8::load(in[5].data()), 0x6u);
  for (int i = 0; i < 8; ++i) {
    CHECK(c.r[i] == 0.0f);
    CHECK(std::bit_cast<std::uint32_t>(c.g[i]) == std::bit_cast<std::uint32_t>(full[1][i]));
    CHECK(std::bit_cast<std::uint32_t>(c.b[i]) == std::bit_cast<std::uint32_t>(full[2][i]));
    CHECK(c.a[i] == 0.0f);
  }
}
