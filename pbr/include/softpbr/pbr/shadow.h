// softpbr/pbr/shadow.h — a light's shadow map and its lookup in lanes (docs/design.md,
// "Shadows").
//
// render() draws the shadow casters' depth as seen from each light that casts shadows
// (Light::shadows) into depth-only targets — the rasterizer's own pipeline, so the depths
// follow its coverage and depth rules exactly — and the shaders multiply that light's
// falloff by shadow_visibility(): the fraction of a fixed 4×4 pattern of texel comparisons
// (percentage-closer filtering) that sees the receiving point lit. Written once against a
// lane type F (float or simd::Lanes) with IEEE basic operations in a fixed order, so every
// lane width, thread count and machine gives the same bits; a light without a map runs
// none of it.
#pragma once

#include <cstddef>
#include <cstdint>

#include <glm/vec3.hpp>

#include "softpbr/simd/simd.h"

namespace softpbr::pbr {

// One light's map: `size` × `size` window depths a face (row 0 at the top, as the
// rasterizer writes them; 1 where nothing was drawn).
struct ShadowMap {
  enum class Kind : std::uint8_t {
    Orthographic,  // a directional light: one face, clip = rows · (p, 1) with w = 1
    Perspective,   // a spot light: one face, clip = rows · (p, 1)
    Cube           // a point light (or a spot too wide for one face): six faces about `position`
  };
  Kind kind = Kind::Orthographic;
  int size = 0;
  // Orthographic and Perspective: world → clip space, row k of the 4×4 matrix the casters
  // were drawn with (rows[k][0..3], the fourth the translation).
  float rows[4][4] = {};
  // Cube: face f (+X, −X, +Y, −Y, +Z, −Z) holds the directions d = p − position whose major
  // axis is f's: x = (u_f · d) / (scale · m), y = (v_f · d) / (scale · m) in clip space with
  // m = |d|'s major component, window depth ((a · m + b) / m) · ½ + ½ as the rasterizer
  // computes it from clip z = a · m + b, w = m (cube_face_axes gives u_f, v_f).
  glm::vec3 position{0.0f};
  float scale = 1.0f, a = 1.0f, b = 0.0f;
  const float* faces[6] = {};  // Cube: each face's depths; the others: faces[0]
  // The world size of a texel where w (Cube: m) is 1: the bias is counted in texels.
  float texel = 0.0f;
};

// The bias, in texels at the receiving point (Holbert 2011, "Saying Goodbye to Shadow Acne";
// docs/design.md, "Shadows"): the point moves kNormalOffset · sin θ texels along its normal
// (θ between normal and light), which raises it kNormalOffset · tan θ texels above its
// tangent plane as the light sees it — the depth a plane at θ changes over that many
// texels, the farthest reach of the 4×4 pattern (2.5 texels along an axis, 3.54 diagonally)
// — and kLightOffset texels towards the light, for the rasterizer's and the lookup's
// rounding.
inline constexpr float kShadowNormalOffset = 4.0f;
inline constexpr float kShadowLightOffset = 1.5f;

// The cube faces' axes: face f's major axis (its sign in the face's parity) and the clip x
// and y directions u_f, v_f, with u_f × v_f = −major (a view looking along the major axis,
// as glm::lookAt builds it, so the winding and culling of the casters are a camera's).
// Index: 0 +X, 1 −X, 2 +Y, 3 −Y, 4 +Z, 5 −Z; component `axis` in [0, 3) with sign ±1.
struct CubeFaceAxes {
  int major_axis, major_sign;
  int u_axis, u_sign;
  int v_axis, v_sign;
};
inline constexpr CubeFaceAxes kCubeFaces[6] = {
    {0, 1, 2, -1, 1, -1},  // +X: u = −z, v = −y
    {0, -1, 2, 1, 1, -1},  // −X: u = +z, v = −y
    {1, 1, 0, 1, 2, 1},    // +Y: u = +x, v = +z
    {1, -1, 0, 1, 2, -1},  // −Y: u = +x, v = −z
    {2, 1, 0, 1, 1, -1},   // +Z: u = +x, v = −y
    {2, -1, 0, -1, 1, -1}, // −Z: u = −x, v = −y
};

namespace detail {
// x clamped to [lo, hi]; NaN to lo.
template <class F>
inline F shadow_clamp(F x, float lo, float hi) {
  const F l(lo);
  return simd::min(simd::select(x >= l, x, l), F(hi));
}
}  // namespace detail

// The fraction of the light reaching `position` (world) in [0, 1]: exactly 1 where no
// texel of the pattern is nearer the light than the point, exactly 0 where every one is.
// n is the unit shading normal, l the unit direction to the light, n_dot_l their dot
// product. The pattern: the texel centres around the point's projection (x, y), with
// i0 = ⌊x − ½⌋ and f = x − ½ − i0, columns i0 − 1 … i0 + 2 weighted 1 − f, 1, 1, f, rows
// likewise (a 3×3 box of bilinear comparisons); the result lit / (lit + shadowed) of the
// weights, in a fixed order.
template <class F>
inline F shadow_visibility(const ShadowMap& m, const simd::Vec3<F>& position, const simd::Vec3<F>& n,
                           const simd::Vec3<F>& l, F n_dot_l) {
  using V3 = simd::Vec3<F>;
  constexpr int N = simd::LaneCount<F>::value;
  const F zero(0.0f), one(1.0f);
  const int size = m.size;
  const float fs = static_cast<float>(size);

  // The texel's world size at the point: w (or m) times m.texel.
  F w0 = one;
  if (m.kind == ShadowMap::Kind::Perspective) {
    w0 = F(m.rows[3][0]) * position.x + F(m.rows[3][1]) * position.y + F(m.rows[3][2]) * position.z + F(m.rows[3][3]);
  } else if (m.kind == ShadowMap::Kind::Cube) {
    const V3 d = position - V3(F(m.position.x), F(m.position.y), F(m.position.z));
    const F ax = simd::max(d.x, zero - d.x), ay = simd::max(d.y, zero - d.y), az = simd::max(d.z, zero - d.z);
    w0 = simd::max(simd::max(ax, ay), az);
  }
  const F texel = simd::max(w0, zero) * F(m.texel);
  // The offsets: sin θ along n, a constant towards the light.
  const F c = simd::clamp(n_dot_l, zero, one);
  const F sin_theta = simd::sqrt(simd::max(one - c * c, zero));
  const V3 p = position + n * (sin_theta * texel * F(kShadowNormalOffset)) + l * (texel * F(kShadowLightOffset));

  // The point in the map: texel coordinates (x, y) and window depth z; the face per lane.
  F x, y, z;
  alignas(64) std::uint32_t face[N > 1 ? N : 1] = {};
  if (m.kind == ShadowMap::Kind::Cube) {
    const V3 d = p - V3(F(m.position.x), F(m.position.y), F(m.position.z));
    const F ax = simd::max(d.x, zero - d.x), ay = simd::max(d.y, zero - d.y), az = simd::max(d.z, zero - d.z);
    const auto x_major = simd::both(ax >= ay, ax >= az);
    const auto y_major = ay >= az;
    // Per major axis and sign: (m, u · d, v · d, face), kCubeFaces' table in selects.
    const auto px = d.x >= zero, py = d.y >= zero, pz = d.z >= zero;
    const F mz = simd::select(pz, d.z, zero - d.z), uz = simd::select(pz, d.x, zero - d.x), vz = zero - d.y;
    const F fz = simd::select(pz, F(4.0f), F(5.0f));
    const F my = simd::select(py, d.y, zero - d.y), uy = d.x, vy = simd::select(py, d.z, zero - d.z);
    const F fy = simd::select(py, F(2.0f), F(3.0f));
    const F mx = simd::select(px, d.x, zero - d.x), ux = simd::select(px, zero - d.z, d.z), vx = zero - d.y;
    const F fx = simd::select(px, F(0.0f), F(1.0f));
    const F mm = simd::select(x_major, mx, simd::select(y_major, my, mz));
    const F u = simd::select(x_major, ux, simd::select(y_major, uy, uz));
    const F v = simd::select(x_major, vx, simd::select(y_major, vy, vz));
    const F f = simd::select(x_major, fx, simd::select(y_major, fy, fz));
    const F major = simd::max(mm, F(1e-30f));
    const F inv = one / (major * F(m.scale));
    x = u * inv;
    y = v * inv;
    z = ((F(m.a) * major + F(m.b)) / major) * F(0.5f) + F(0.5f);
    if constexpr (N == 1) {
      face[0] = static_cast<std::uint32_t>(f);
    } else {
      simd::split_whole(f, face);
    }
  } else {
    const auto row = [&](int k) {
      return F(m.rows[k][0]) * p.x + F(m.rows[k][1]) * p.y + F(m.rows[k][2]) * p.z + F(m.rows[k][3]);
    };
    x = row(0);
    y = row(1);
    z = row(2);
    if (m.kind == ShadowMap::Kind::Perspective) {
      const F inv = one / simd::max(row(3), F(1e-30f));  // behind the light: w raised (no light reaches there)
      x = x * inv;
      y = y * inv;
      z = z * inv;
    }
    z = z * F(0.5f) + F(0.5f);
  }
  // A point beyond the far plane is not shadowed by what lies in front of it only because
  // the map ends: z at most 1, the clear value (an empty texel never shadows).
  z = simd::min(z, one);
  // Window coordinates as the rasterizer's viewport transform (row 0 at the top), less the
  // half texel of the centres, clamped so that the pattern's 4×4 texels lie in the face.
  const F half(0.5f * fs);
  const F gx = detail::shadow_clamp((x + one) * half - F(0.5f), 1.0f, fs - 3.0f);
  const F gy = detail::shadow_clamp((one - y) * half - F(0.5f), 1.0f, fs - 3.0f);

  // The 4×4 depths of each lane, from its face.
  F fx, fy;
  F taps[16];
  const auto stride = static_cast<std::size_t>(size);
  if constexpr (N == 1) {
    const auto ix = static_cast<std::uint32_t>(gx), iy = static_cast<std::uint32_t>(gy);
    fx = gx - static_cast<float>(ix);
    fy = gy - static_cast<float>(iy);
    const float* base = m.faces[face[0]] + (static_cast<std::size_t>(iy) - 1) * stride + (ix - 1);
    for (int r = 0; r < 4; ++r)
      for (int k = 0; k < 4; ++k) taps[4 * r + k] = base[static_cast<std::size_t>(r) * stride + static_cast<std::size_t>(k)];
  } else {
    alignas(64) std::uint32_t ix[N], iy[N];
    fx = simd::split_whole(gx, ix);
    fy = simd::split_whole(gy, iy);
    alignas(64) float values[16][N];
    for (int i = 0; i < N; ++i) {
      const float* base = m.faces[face[i]] + (static_cast<std::size_t>(iy[i]) - 1) * stride + (ix[i] - 1);
      for (int r = 0; r < 4; ++r)
        for (int k = 0; k < 4; ++k)
          values[4 * r + k][i] = base[static_cast<std::size_t>(r) * stride + static_cast<std::size_t>(k)];
    }
    for (int t = 0; t < 16; ++t) taps[t] = F::load(values[t]);
  }
  // The weights: columns 1 − fx, 1, 1, fx; rows likewise. Each row's lit and shadowed sums,
  // then the rows'.
  const F wx[4] = {one - fx, one, one, fx};
  const F wy[4] = {one - fy, one, one, fy};
  F lit = zero, shadowed = zero;
  for (int r = 0; r < 4; ++r) {
    F row_lit = zero, row_shadowed = zero;
    for (int k = 0; k < 4; ++k) {
      const auto passes = z <= taps[4 * r + k];
      row_lit = row_lit + simd::select(passes, wx[k], zero);
      row_shadowed = row_shadowed + simd::select(passes, zero, wx[k]);
    }
    lit = lit + row_lit * wy[r];
    shadowed = shadowed + row_shadowed * wy[r];
  }
  // lit + shadowed > 0: the middle weights are 1.
  return lit / (lit + shadowed);
}

}  // namespace softpbr::pbr
