// softpbr/pbr/layered_shading.h — the reflectance equation with glTF's material extensions:
// KHR_materials_ior and _specular (the dielectric's F0 and F90), _sheen and _clearcoat.
//
// The layers stack as the extensions' specifications and the glTF Sample Viewer stack them:
//
//   f = mix(f_sheen + f_base · s, f_coat, coat · Fc)
//
//   f_base  the core material (shading.h) with the dielectric's F0 = w · min(F0(ior) · colour, 1)
//           and F90 = w (w the specular weight): F = F0 + (F90 − F0)(1 − v·h)⁵ with the mixed
//           F0 = mix(F0_d, c, metallic) and F90 = mix(w, 1, metallic); the diffuse term's
//           weight 1 − F = (1 − F0)(1 − m⁵) + (1 − F90) m⁵ (shading.h's kD, extended).
//   f_sheen sheen colour · D_Charlie · V_Charlie (brdf.h), and s = 1 − max(colour) · E(n·v),
//           E the sheen's directional albedo (sheen_table), the specification's simplified
//           albedo scaling (its n·v term only), for direct and image-based light alike.
//   f_coat  a GGX lobe of the coat's roughness and normal (the geometric normal, or the
//           coat's own normal map), Fc = 0.04 + 0.96 (1 − v·h)⁵ per light (F0 = 0.04,
//           ior 1.5, as the extension fixes it); in image-based light Fc uses the coat's
//           n·v and the coat reflects prefiltered(r_coat) · coat · Fc: exactly the energy
//           the base loses (the Sample Viewer's mix; the split sum's F0·A + B would add
//           what Fresnel with roughness counts twice: a white furnace returned 1.13 at
//           n·v = 0.3), times ao and the specular occlusion as the base's specular.
//           Emission is seen through the coat: times 1 − coat · Fc(n·v).
//
// The sheen's image-based light reads the prefiltered GGX level of the sheen roughness along
// the mirror direction (as Filament's cloth does; there is no Charlie-prefiltered map),
// times colour · E(n·v).
//
// Each layer is off for a whole draw when its factor is 0 (a uniform: LayerLanes::coat,
// ::sheen), and its operations then do not run. A coat whose factor is 0 only at some
// pixels (a texture) gives f_base · (1 − 0) + 0 there: the base's bits. With F0(ior) = 0.04,
// a white specular colour and w = 1 (defaults), f_base is the core shader's, bit for bit:
// every added operation multiplies by 1 or adds 0 (tests/test_layers.cpp).
#pragma once

#include <cstddef>
#include <span>
#include <type_traits>

#include "softpbr/pbr/brdf.h"
#include "softpbr/pbr/environment_lookup.h"
#include "softpbr/pbr/shading.h"

namespace softpbr::pbr {

// F0 of the clear coat (KHR_materials_clearcoat: ior 1.5).
inline constexpr float kCoatF0 = 0.04f;

template <class F>
struct CoatLanes {
  F factor;         // coat factor × texture, in [0, 1]
  F roughness;      // perceptual, clamped to [kMinRoughness, 1]
  F alpha;          // roughness²
  F k;              // k_direct(roughness)
  Vec3L<F> normal;  // the coat's normal (need not be unit)
};

template <class F>
struct SheenLanes {
  Vec3L<F> color;  // linear sheen colour
  F roughness;     // perceptual, clamped to [kMinSheenRoughness, 1]
};

// The layers of a material per lane. `coat` and `sheen` say whether the layer is on for
// the draw (uniform); their lanes are read only then.
template <class F>
struct LayerLanes {
  DielectricLanes<F> dielectric;
  bool coat = false;
  bool sheen = false;
  CoatLanes<F> coat_lanes;
  SheenLanes<F> sheen_lanes;
};

// The dielectric's lanes from F0(ior) (f0_from_ior), the specular colour and weight w, and
// the material's metallic: F0_d = w · min(F0(ior) · colour, 1), F90 = w + (1 − w) metallic.
template <class F>
inline DielectricLanes<F> dielectric_lanes(float f0_ior, const Vec3L<F>& specular_color, F weight, F metallic) {
  const F one(1.0f);
  const Vec3L<F> f0 = specular_color * F(f0_ior);
  DielectricLanes<F> d;
  d.f0 = Vec3L<F>(simd::min(f0.x, one), simd::min(f0.y, one), simd::min(f0.z, one)) * weight;
  d.weight = weight;
  d.f90 = weight + (one - weight) * metallic;
  return d;
}

// The mixed F0 of the layered material: mix(F0_d, base colour, metallic), with the same
// operations as f0_of (brdf.h), whose 0.04 F0_d replaces.
template <class F>
inline Vec3L<F> layered_f0(const DielectricLanes<F>& d, const Vec3L<F>& base_color, F metallic) {
  return d.f0 + (base_color - d.f0) * metallic;
}

// The prefiltered radiance of the GGX lobe at n seen from v (the mirror direction bent
// toward n by the lobe's width, as ibl() bends it), for a coat or a sheen.
template <class F>
inline Vec3L<F> lobe_radiance(const PreparedEnvironment& e, const Vec3L<F>& n, const Vec3L<F>& v, F n_dot_v, F alpha,
                              F roughness) {
  const F one(1.0f);
  const Vec3L<F> r0 = n * (n_dot_v + n_dot_v) - v;
  const F s = one - alpha;
  const F f = s * (simd::sqrt(s) + alpha);
  const Vec3L<F> r = n + (r0 - n) * f;
  const EnvVec3<F> pre = env_radiance(e, to_environment(e, r.x, r.y, r.z), roughness);
  return {pre.x, pre.y, pre.z};
}

// The largest of a colour's three channels.
template <class F>
inline F max3(const Vec3L<F>& c) {
  return simd::max(simd::max(c.x, c.y), c.z);
}

// Outgoing radiance with the layers: shade() (shading.h) of the layered material. m.f0
// must be layered_f0(layers.dielectric, …).
template <class F>
inline Vec3L<F> shade_layered(const MaterialLanes<F>& m, const LayerLanes<F>& layers,
                              std::span<const PreparedLight> lights, const glm::vec3& ambient, const Vec3L<F>& position,
                              const Vec3L<F>& n_in, const Vec3L<F>& v, const PreparedEnvironment* env,
                              const std::type_identity_t<F>* occlusion) {
  const F zero(0.0f), one(1.0f);
  const DielectricLanes<F>& d = layers.dielectric;
  const MaterialTerms<F> mt = material_terms(m);
  // F90 − F0 and the diffuse weight's (1 − F90) m⁵ part, c/π (1 − metallic) max(1 − F90, 0).
  const Vec3L<F> f90_minus_f0 = Vec3L<F>(d.f90) - m.f0;
  const Vec3L<F> diffuse_f90 = m.albedo * (simd::max(one - d.f90, zero) * (m.one_minus_metallic * Fd_Lambert<F>()));
  const Vec3L<F> n = normalize_or(n_in, v);
  const ViewTerms<F> vt = view_terms(n, v);

  // The sheen: its albedo scaling and, per pixel, Λ(n·v) and l(1/2) of its visibility.
  F sheen_scale = one, sheen_alpha = one, sheen_E = zero, lambda_v = zero, l_half = zero;
  if (layers.sheen) {
    const SheenLanes<F>& sh = layers.sheen_lanes;
    sheen_alpha = sh.roughness * sh.roughness;
    sheen_E = env_sheen_albedo(vt.NoV, sh.roughness);
    sheen_scale = one - max3(sh.color) * sheen_E;
    l_half = sheen_l(F(0.5f), sheen_alpha);
    lambda_v = lambda_sheen(vt.NoV, sheen_alpha, l_half);
  }
  // The coat: its unit normal and n·v.
  Vec3L<F> nc = n;
  ViewTerms<F> vtc = vt;
  F coat_alpha2 = zero;
  if (layers.coat) {
    nc = normalize_or(layers.coat_lanes.normal, n);
    vtc = view_terms(nc, v);
    coat_alpha2 = layers.coat_lanes.alpha * layers.coat_lanes.alpha;
  }

  Vec3L<F> lo(zero);
  constexpr std::size_t kBatch = 8;  // as shade(): every light's sample first, then its shading
  LightSampleLanes<F> samples[kBatch];
  for (std::size_t first = 0; first < lights.size(); first += kBatch) {
    const std::size_t count = std::min(kBatch, lights.size() - first);
    for (std::size_t i = 0; i < count; ++i) samples[i] = sample_light(lights[first + i], position);
    for (std::size_t i = 0; i < count; ++i) {
      const LightSampleLanes<F>& s = samples[i];
      const Vec3L<F>& l = s.to_light;
      const F n_dot_l = simd::dot(n, l);
      const F nc_dot_l = layers.coat ? simd::dot(nc, l) : n_dot_l;
      const auto lit = simd::max(n_dot_l, nc_dot_l) > zero;
      if (!simd::any(lit)) continue;
      const F NoL = simd::clamp(n_dot_l, zero, one);
      const HalfTerms<F> h = half_terms(l, v);
      const F w = NoL * s.falloff;
      const F specular = ggx_DV(h, n, n_dot_l, vt.n_dot_v, NoL, vt.NoV, m.alpha, mt.alpha2, m.k) * w;
      const F m5w = h.m5 * w;
      const Vec3L<F> Fr = m.f0 + f90_minus_f0 * h.m5;
      Vec3L<F> f = mt.diffuse * ((one - h.m5) * w) + diffuse_f90 * m5w + Fr * specular;
      if (layers.sheen) {
        const Vec3L<F> u_across = h.u - n * (n_dot_l + vt.n_dot_v);
        const F sin2h = simd::min(simd::dot(u_across, u_across) / h.t, one);
        const F lambda_l = lambda_sheen(NoL, sheen_alpha, l_half);
        const F sheen = D_Charlie(sin2h, sheen_alpha) * V_Charlie_times_NoL(lambda_v, lambda_l, vt.NoV, NoL) *
                        simd::select(n_dot_l > zero, s.falloff, zero);
        f = f * sheen_scale + layers.sheen_lanes.color * sheen;
      }
      if (layers.coat) {
        const CoatLanes<F>& c = layers.coat_lanes;
        const F NoLc = simd::clamp(nc_dot_l, zero, one);
        const F fc = c.factor * (F(kCoatF0) + F(1.0f - kCoatF0) * h.m5);
        const F coat = ggx_DV(h, nc, nc_dot_l, vtc.n_dot_v, NoLc, vtc.NoV, c.alpha, coat_alpha2, c.k) * NoLc *
                       s.falloff * fc;
        f = f * (one - fc) + Vec3L<F>(coat);
      }
      lo = simd::select(lit, lo + f * lanes<F>(lights[first + i].radiance), lo);
    }
  }

  // Image-based (or the constant ambient) light, then emission.
  Vec3L<F> indirect = env != nullptr ? ibl<F, true>(m, *env, n, v, occlusion, &d) : lanes<F>(ambient) * m.albedo * m.ao;
  // What the layers' image-based light is multiplied by: ao and the specular occlusion.
  F specular_ao = m.ao;
  if (env != nullptr && occlusion != nullptr) specular_ao = (one - (one - *occlusion) * F(env->specular_occlusion)) * m.ao;
  if (layers.sheen) {
    indirect = indirect * sheen_scale;
    if (env != nullptr) {
      const SheenLanes<F>& sh = layers.sheen_lanes;
      const Vec3L<F> pre = lobe_radiance(*env, n, v, vt.n_dot_v, sheen_alpha, sh.roughness);
      indirect = indirect + pre * sh.color * (sheen_E * specular_ao);
    }
  }
  Vec3L<F> emissive = m.emissive;
  if (layers.coat) {
    const CoatLanes<F>& c = layers.coat_lanes;
    const F cv = one - vtc.NoV, cv2 = cv * cv;
    const F cv5 = cv2 * cv2 * cv;
    const F fc = c.factor * (F(kCoatF0) + F(1.0f - kCoatF0) * cv5);
    indirect = indirect * (one - fc);
    emissive = emissive * (one - fc);
    if (env != nullptr) {
      const Vec3L<F> pre = lobe_radiance(*env, nc, v, vtc.n_dot_v, c.alpha, c.roughness);
      indirect = indirect + pre * (fc * specular_ao);
    }
  }
  return indirect + lo + emissive;
}

}  // namespace softpbr::pbr
