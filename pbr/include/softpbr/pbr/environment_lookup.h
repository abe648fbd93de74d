// softpbr/pbr/environment_lookup.h — image-based lighting as the shaders read it: the
// environment prepared for a frame (its rotation and intensity, and pointers to its
// irradiance coefficients and prefiltered levels) and its lookups in lane form, with the
// split-sum DFG table.
//
// The shaders and their tile kernels include this header, not environment.h (the
// Environment class: loading, prefiltering, the disk cache), so that changing how an
// environment is built or loaded does not recompile the kernels. See environment.h for
// the maps, their conventions and docs/design.md, "Image-based lighting", for the maths.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "softpbr/pbr/light.h"
#include "softpbr/raster/texture.h"
#include "softpbr/simd/simd.h"

namespace softpbr::pbr {

// The prefiltered levels of an environment and the lookup's key of each: level l holds the
// radiance prefiltered with the GGX lobe of α = kEnvironmentLevelAlpha[l] (α = roughness²),
// except level 0, the map itself, which the lookups read at α ≤ kEnvironmentLevelAlpha[0]
// (the shading's roughness floor kMinRoughness, squared: a mirror reads the unfiltered map).
// The levels double α about every step (Environment::level_side sizes each to its lobe), so
// near-mirrors have levels of their own; between two levels the lookup blends linearly in
// α (docs/design.md, "Image-based lighting").
inline constexpr int kEnvironmentLevels = 8;
inline constexpr float kEnvironmentLevelAlpha[kEnvironmentLevels] = {0.045f * 0.045f, 0.008f, 0.02f, 0.05f,
                                                                     0.11f,           0.22f,  0.45f, 1.0f};
// The irradiance map: an octahedral map of this side (and its one-texel border) of the
// map's exact cosine convolution, divided by π.
inline constexpr int kIrradianceSize = 32;

// The split-sum BRDF table: kDfgSize² texels, u = n·v, v = perceptual roughness, at texel
// centres; r = A, g = B (specular = F0·A + B), b = A + B (the single-scattering energy).
// Computed once, on first use, in double, with kDfgSamples Hammersley samples a texel.
inline constexpr int kDfgSize = 32;
inline constexpr int kDfgSamples = 1024;
const raster::Texture& dfg_table();
// The table's value (A, B) for one point, by the same integration in double with
// `samples` Hammersley samples (the tests' reference).
glm::dvec2 dfg_reference(double NoV, double roughness, int samples);

// The sheen layer's directional albedo E(n·v, roughness) = ∫ f_sheen (n·l) dω_l of the
// Charlie sheen of colour 1 (brdf.h: D_Charlie and the Charlie visibility), what its
// albedo scaling (1 − max(colour) · E) and its image-based light read: kSheenSize² texels,
// u = n·v, v = sheen roughness at texel centres, min(E, 1) in r (g, b the same, a 1). Computed
// once, on first use, in double with dmath, over a kSheenSamples × kSheenSamples grid of
// light directions (n·l by midpoints, the azimuth over half the circle, doubled).
inline constexpr int kSheenSize = 32;
inline constexpr int kSheenSamples = 48;
const raster::Texture& sheen_table();
// The table's value for one point by the same integration with `samples`² directions (the
// tests' reference).
double sheen_albedo_reference(double NoV, double roughness, int samples);

// What the shaders read, prepared once per frame.
struct PreparedEnvironment {
  const Environment* map = nullptr;
  // What the lookups read of map, taken by prepare_environment: its irradiance map
  // (Environment::irradiance()) and levels.
  const raster::Texture* irradiance = nullptr;
  std::array<const raster::Texture*, kEnvironmentLevels> levels{};
  float cos_r = 1.0f, sin_r = 0.0f;  // the rotation, by dmath
  float intensity = 1.0f;
  bool multiscatter = true;
  // Screen-space ambient occlusion of this light (docs/design.md, "Image-based lighting"):
  // one factor in [0, 1] a pixel, row-major, occlusion_width × occlusion_height (the
  // frame's pixels), read at each lane's pixel by env_occlusion. Null: not occluded (the
  // background, blended and masked objects, occlusion off), and ibl() runs as without it.
  const float* occlusion = nullptr;
  int occlusion_width = 0, occlusion_height = 0;
  // How much of the occlusion the specular term takes: it is multiplied by
  // 1 − specular_occlusion · (1 − occlusion).
  float specular_occlusion = 1.0f;
};

// The environment of a scene (EnvironmentLighting, light.h) prepared for a frame. Throws
// std::invalid_argument naming the field (non-finite or negative intensity, non-finite
// rotation).
PreparedEnvironment prepare_environment(const EnvironmentLighting& e);

// --- Lookups in lane form (F = float or simd lanes; the same bits per lane at any width). ---

template <class F>
struct EnvVec3 {
  F x, y, z;
};

// World direction → the environment's own frame (the inverse rotation).
template <class F>
inline EnvVec3<F> to_environment(const PreparedEnvironment& e, F x, F y, F z) {
  const F c(e.cos_r), s(e.sin_r);
  return {c * x - s * z, y, s * x + c * z};
}

// Octahedral texture coordinates of direction d (any non-zero length) on a level of side
// `size` with its one-texel border.
template <class F>
inline void env_octahedral(const EnvVec3<F>& d, int size, F& u, F& v) {
  const F zero(0.0f), one(1.0f);
  auto abs = [&](F a) { return simd::max(a, zero - a); };
  auto sign = [&](F a) { return simd::select(a < zero, F(-1.0f), one); };
  const F l1 = abs(d.x) + abs(d.y) + abs(d.z);
  const F inv = one / simd::select(l1 > zero, l1, one);
  F px = d.x * inv, pz = d.z * inv;
  const auto lower = d.y < zero;
  const F fx = (one - abs(pz)) * sign(px), fz = (one - abs(px)) * sign(pz);
  px = simd::select(lower, fx, px);
  pz = simd::select(lower, fz, pz);
  // [−1, 1] → texels [1, size + 1] of size + 2.
  const F scale(0.5f * static_cast<float>(size)), offset(0.5f * static_cast<float>(size) + 1.0f);
  const F inv_full(1.0f / static_cast<float>(size + 2));
  u = (px * scale + offset) * inv_full;
  v = (pz * scale + offset) * inv_full;
}

// A bilinear, clamp-to-edge lookup of a single-level float texture (the environment's
// levels and the DFG table), RGB: per lane, x = clamp(u·W − ½, 0, W − 1) and likewise y,
// the four texels around it weighted (1 − fx, fx) then (1 − fy, fy) — the same float
// operations for each lane at every width. Non-finite coordinates read texel 0. In lane
// form the weights and the blend are lane operations; only the texel addresses are
// per lane, each texel one 16-byte load (simd::load_deinterleave4 of the records).
template <class F>
inline EnvVec3<F> env_bilinear(const raster::Texture& t, F u, F v) {
  constexpr int N = simd::LaneCount<F>::value;
  const int w = t.width(), h = t.height();
  const float fw = static_cast<float>(w), fh = static_cast<float>(h);
  const F x = simd::clamp(u * F(fw) - F(0.5f), F(0.0f), F(fw - 1.0f));
  const F y = simd::clamp(v * F(fh) - F(0.5f), F(0.0f), F(fh - 1.0f));
  const float* texels = t.texels_f().data();
  const auto row = static_cast<std::size_t>(w) * 4;
  if constexpr (N == 1) {
    const float xi = x >= 0.0f ? x : 0.0f, yi = y >= 0.0f ? y : 0.0f;  // NaN → 0
    const int x0 = static_cast<int>(xi), y0 = static_cast<int>(yi);
    const float fx = xi - static_cast<float>(x0), fy = yi - static_cast<float>(y0);
    const int x1 = x0 + 1 < w ? x0 + 1 : x0, y1 = y0 + 1 < h ? y0 + 1 : y0;
    const float* r0 = texels + static_cast<std::size_t>(y0) * row;
    const float* r1 = texels + static_cast<std::size_t>(y1) * row;
    const float* c00 = r0 + 4 * x0;
    const float* c10 = r0 + 4 * x1;
    const float* c01 = r1 + 4 * x0;
    const float* c11 = r1 + 4 * x1;
    float out[3];
    for (int c = 0; c < 3; ++c) {
      const float top = c00[c] * (1.0f - fx) + c10[c] * fx;
      const float bottom = c01[c] * (1.0f - fx) + c11[c] * fx;
      out[c] = top * (1.0f - fy) + bottom * fy;
    }
    return {out[0], out[1], out[2]};
  } else {
    const F zero(0.0f), one(1.0f);
    const F xi = simd::select(x >= zero, x, zero), yi = simd::select(y >= zero, y, zero);  // NaN → 0
    alignas(64) std::uint32_t xs[N], ys[N];
    const F fx = simd::split_whole(xi, xs), fy = simd::split_whole(yi, ys);
    const float* corner[4][N];  // (x0, y0), (x1, y0), (x0, y1), (x1, y1)
    for (int i = 0; i < N; ++i) {
      const std::size_t a = xs[i], b = ys[i];
      const std::size_t a1 = a + 1 < static_cast<std::size_t>(w) ? a + 1 : a;
      const std::size_t b1 = b + 1 < static_cast<std::size_t>(h) ? b + 1 : b;
      const float* r0 = texels + b * row;
      const float* r1 = texels + b1 * row;
      corner[0][i] = r0 + 4 * a;
      corner[1][i] = r0 + 4 * a1;
      corner[2][i] = r1 + 4 * a;
      corner[3][i] = r1 + 4 * a1;
    }
    F c[4][4];
    for (int k = 0; k < 4; ++k) simd::load_deinterleave4<N>(corner[k], c[k][0], c[k][1], c[k][2], c[k][3]);
    const F gx = one - fx, gy = one - fy;
    F out[3];
    for (int ch = 0; ch < 3; ++ch) {
      const F top = c[0][ch] * gx + c[1][ch] * fx;
      const F bottom = c[2][ch] * gx + c[3][ch] * fx;
      out[ch] = top * gy + bottom * fy;
    }
    return {out[0], out[1], out[2]};
  }
}

// Irradiance / π at direction d (environment frame, any non-zero length), times the
// intensity: the irradiance map, bilinear.
template <class F>
inline EnvVec3<F> env_irradiance(const PreparedEnvironment& e, const EnvVec3<F>& d) {
  F u, v;
  env_octahedral(d, kIrradianceSize, u, v);
  const EnvVec3<F> c = env_bilinear(*e.irradiance, u, v);
  const F k(e.intensity);
  return {c.x * k, c.y * k, c.z * k};
}

// The level coordinate of α: lod = l + (α − α_l) / (α_{l+1} − α_l) between levels l and
// l + 1, 0 below α_0 and kEnvironmentLevels − 1 from α = 1: a sum of clamped ramps, one per
// pair of levels, so every lane runs the same operations.
template <class F>
inline F env_lod(F alpha) {
  const F zero(0.0f), one(1.0f);
  F lod = zero;
  for (int l = 0; l + 1 < kEnvironmentLevels; ++l) {
    const float inv = 1.0f / (kEnvironmentLevelAlpha[l + 1] - kEnvironmentLevelAlpha[l]);
    lod = lod + simd::clamp((alpha - F(kEnvironmentLevelAlpha[l])) * F(inv), zero, one);
  }
  return lod;
}

// The prefiltered radiance along d (environment frame) for perceptual roughness in [0, 1],
// times the intensity: the two levels around env_lod(roughness²), blended linearly. Each
// lane adds w · c for its own two levels only (w = 1 − |lod − l|), so a lane has the same
// bits whatever the other lanes' roughness.
template <class F>
inline EnvVec3<F> env_radiance(const PreparedEnvironment& e, const EnvVec3<F>& d, F roughness) {
  const F zero(0.0f), one(1.0f);
  const F r = simd::clamp(roughness, zero, one);
  const F lod = env_lod(r * r);
  F red = zero, g = zero, b = zero;
  for (int l = 0; l < kEnvironmentLevels; ++l) {
    const F dl = lod - F(static_cast<float>(l));
    const F w = simd::max(one - simd::max(dl, zero - dl), zero);
    if (!simd::any(w > zero)) continue;
    F u, v;
    const raster::Texture& level = *e.levels[static_cast<std::size_t>(l)];
    env_octahedral(d, level.width() - 2, u, v);  // Environment::level_size()
    const EnvVec3<F> c = env_bilinear(level, u, v);
    red = red + w * c.x;
    g = g + w * c.y;
    b = b + w * c.z;
  }
  const F k(e.intensity);
  return {red * k, g * k, b * k};
}

// The same for a roughness shared by every lane (an untextured material, the background):
// the levels and weights are found once, not per lane — the same bits as the lane form.
template <class F>
inline EnvVec3<F> env_radiance_uniform(const PreparedEnvironment& e, const EnvVec3<F>& d, float roughness) {
  const float rc = simd::clamp(roughness, 0.0f, 1.0f);
  const float lod = env_lod(rc * rc);
  F r(0.0f), g(0.0f), b(0.0f);
  for (int l = 0; l < kEnvironmentLevels; ++l) {
    const float dl = lod - static_cast<float>(l);
    const float w = simd::max(1.0f - simd::max(dl, 0.0f - dl), 0.0f);
    if (!(w > 0.0f)) continue;
    F u, v;
    const raster::Texture& level = *e.levels[static_cast<std::size_t>(l)];
    env_octahedral(d, level.width() - 2, u, v);  // Environment::level_size()
    const EnvVec3<F> c = env_bilinear(level, u, v);
    r = r + F(w) * c.x;
    g = g + F(w) * c.y;
    b = b + F(w) * c.z;
  }
  const F k(e.intensity);
  return {r * k, g * k, b * k};
}

// The occlusion factor of the pixel each lane shades (pixel centres pos_x, pos_y, as a
// FragmentPacket holds them; e.occlusion must be set): a per-lane gather of the pixel's
// float, so every lane reads its own pixel's bits at any width. Coordinates outside the
// buffer (or NaN, in lanes past a packet's last pixel) read its nearest row and column.
template <class F>
inline F env_occlusion(const PreparedEnvironment& e, F pos_x, F pos_y) {
  constexpr int N = simd::LaneCount<F>::value;
  const F zero(0.0f);
  const F x = simd::select(pos_x >= zero, pos_x, zero), y = simd::select(pos_y >= zero, pos_y, zero);  // NaN → 0
  const auto w = static_cast<std::uint32_t>(e.occlusion_width), h = static_cast<std::uint32_t>(e.occlusion_height);
  const F xc = simd::min(x, F(static_cast<float>(w) - 0.5f)), yc = simd::min(y, F(static_cast<float>(h) - 0.5f));
  if constexpr (N == 1) {
    const auto xi = static_cast<std::uint32_t>(xc), yi = static_cast<std::uint32_t>(yc);
    return e.occlusion[static_cast<std::size_t>(yi) * w + xi];
  } else {
    alignas(64) std::uint32_t xs[N], ys[N];
    simd::split_whole(xc, xs);
    simd::split_whole(yc, ys);
    alignas(64) float out[N];
    for (int i = 0; i < N; ++i) out[i] = e.occlusion[static_cast<std::size_t>(ys[i]) * w + xs[i]];
    return F::load(out);
  }
}

// The split-sum table at (n·v, roughness): A and B.
template <class F>
inline void env_dfg(F NoV, F roughness, F& a, F& b) {
  const EnvVec3<F> c = env_bilinear(dfg_table(), NoV, roughness);
  a = c.x;
  b = c.y;
}

// The sheen's directional albedo at (n·v, sheen roughness).
template <class F>
inline F env_sheen_albedo(F NoV, F roughness) {
  return env_bilinear(sheen_table(), NoV, roughness).x;
}

}  // namespace softpbr::pbr
