// softpbr/pbr/shading.h — the reflectance equation over all lights, and the PBR shader.
//
//   Lo = Σ_lights (kD · c/π + D · G · F / (4 (n·l)(n·v))) · Li · (n·l)
//        + ambient · c · ao + emissive,          kD = (1 − F)(1 − metallic)
//
// evaluated with brdf.h's terms: D · G / (4 (n·l)(n·v)) as DV_GGX_SchlickSmith_t (D_GGX and
// G_Smith with Schlick-GGX, k = (r+1)²/8, folded into one division, n·h without forming
// h), Schlick's Fresnel from schlick_weight, and Fd_Lambert. Nothing here
// produces NaN or Inf for finite inputs: roughness is raised to kMinRoughness, n·v is
// clamped to kMinNoV (interpolated normals may face away from the viewer), lights with
// n·l ≤ 0 are skipped, and zero-length normals fall back to the view direction.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <memory>
#include <span>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "softpbr/pbr/brdf.h"
#include "softpbr/pbr/environment_lookup.h"
#include "softpbr/pbr/light.h"
#include "softpbr/pbr/material.h"
#include "softpbr/pbr/mesh.h"
#include "softpbr/pbr/shadow.h"
#include "softpbr/raster/shader.h"
#include "softpbr/simd/simd.h"

namespace softpbr::pbr {

// A material ready for shading: roughness clamped to [kMinRoughness, 1], everything else
// checked to be finite and in range.
struct ShadingMaterial {
  glm::vec3 albedo;     // base colour
  glm::vec3 f0;         // mix(0.04, base colour, metallic)
  float metallic;
  float roughness;      // perceptual, clamped
  float alpha;          // roughness²
  float k;              // (roughness + 1)² / 8
  float ao;
  glm::vec3 emissive;
};

// Throws std::invalid_argument naming the field for NaN/Inf or out-of-range values
// (metallic, roughness and ao must be in [0, 1]; colours non-negative).
ShadingMaterial prepare_material(const Material& m);

// The shading functions are written once against a lane type F: float for one pixel,
// simd::Vec<N> for N pixels, with the same operations per lane (simd.h). The glm
// overloads below are the same code for one point.

template <class F>
using Vec3L = simd::Vec3<F>;

template <class F>
inline Vec3L<F> lanes(const glm::vec3& v) {
  return {F(v.x), F(v.y), F(v.z)};
}

// v / |v|, or `fallback` when v has zero length (or is not finite).
template <class F>
inline Vec3L<F> normalize_or(const Vec3L<F>& v, const Vec3L<F>& fallback) {
  const F len2 = simd::dot(v, v);
  // "0 < len2 < ∞" as a chain — the second test reads the first select's result — rather
  // than one combined mask or two tests of len2: the same lanes, each step a compare and a
  // blend at any width.
  const F one(1.0f), inf(std::numeric_limits<float>::infinity());
  const F positive = simd::select(len2 > F(0.0f), len2, inf);  // 0, negative and NaN → ∞
  const F len = simd::sqrt(simd::select(positive < inf, positive, one));
  const Vec3L<F> unit = v * (one / len);  // one division, not three
  return simd::select(positive < inf, unit, fallback);
}

// A material per lane: what the equation reads, uniform (lanes(ShadingMaterial)) or
// from textures (TexturedPbrShader).
template <class F>
struct MaterialLanes {
  Vec3L<F> albedo;
  Vec3L<F> f0;
  F one_minus_metallic;
  F alpha;  // roughness²
  F k;      // (roughness + 1)² / 8
  F ao;
  Vec3L<F> emissive;
  F roughness;  // perceptual, clamped (what the environment's lookups read)
  // The roughness when every lane has the same (an untextured material), else −1: lets
  // the environment's lookups pick their levels once (the same bits either way).
  float uniform_roughness = -1.0f;
};

template <class F>
inline MaterialLanes<F> lanes(const ShadingMaterial& m) {
  return {lanes<F>(m.albedo), lanes<F>(m.f0), F(1.0f - m.metallic), F(m.alpha), F(m.k), F(m.ao),
          lanes<F>(m.emissive), F(m.roughness), m.roughness};
}

// What the BRDF derives from the material alone: the same for every pixel of an
// untextured draw (PbrShader builds it once per draw and tile, packet_uniforms).
template <class F>
struct MaterialTerms {
  Vec3L<F> one_minus_f0;  // 1 − F0: F = F0 + (1 − F0) m⁵
  // c/π (1 − metallic) max(1 − F0, 0): the diffuse term kD c/π = (1 − F)(1 − metallic) c/π
  // is this times (1 − m⁵), as 1 − F = (1 − F0)(1 − m⁵) with 1 − m⁵ in [0, 1]. The max
  // keeps a base colour above 1 (accepted, see prepare_material), whose F exceeds 1, from a
  // negative diffuse weight.
  Vec3L<F> diffuse;
  F alpha2;  // α² (α = roughness²), D's
};

template <class F>
inline MaterialTerms<F> material_terms(const MaterialLanes<F>& m) {
  MaterialTerms<F> mt;
  mt.one_minus_f0 = Vec3L<F>(F(1.0f)) - m.f0;
  const F w = m.one_minus_metallic * Fd_Lambert<F>();
  mt.diffuse = Vec3L<F>(simd::max(mt.one_minus_f0.x, F(0.0f)) * w, simd::max(mt.one_minus_f0.y, F(0.0f)) * w,
                        simd::max(mt.one_minus_f0.z, F(0.0f)) * w) *
               m.albedo;
  mt.alpha2 = m.alpha * m.alpha;
  return mt;
}

// What the BRDF needs of n and v alone, computed once per pixel for all its lights.
template <class F>
struct ViewTerms {
  F n_dot_v;  // n·v (s = n·(l + v) is taken as n·l + n·v)
  F NoV;      // n·v clamped to [kMinNoV, 1]
};

template <class F>
inline ViewTerms<F> view_terms(const Vec3L<F>& n, const Vec3L<F>& v) {
  ViewTerms<F> vt;
  vt.n_dot_v = simd::dot(n, v);
  vt.NoV = simd::clamp(vt.n_dot_v, F(kMinNoV), F(1.0f));
  return vt;
}

// The BRDF f(l, v) = kD · c/π + D · G · F / (4 (n·l)(n·v)) for unit n, l, v, times a
// weight w (the shader passes n·l; brdf() below 1, whose multiplies are then exact).
// h = (l + v) / |l + v| is never formed: n·h and v·h come from s = n·(l + v), the part of
// l + v across n and t = |l + v|² (D_GGX_denominator_t, DV_GGX_SchlickSmith_t, VoH_from_t
// in brdf.h), so a light costs the one division of D · V and the square root of v·h.
//
// The half vector's terms are apart (HalfTerms, ggx_DV) so that the layers
// (layered_shading.h) evaluate another normal's lobe for the same light.
template <class F>
struct HalfTerms {
  Vec3L<F> u;  // l + v
  F t_raw;     // |u|²
  F t;         // |u|², at least kMinHalfLength2
  F m5;        // schlick_weight(v·h)
};

template <class F>
inline HalfTerms<F> half_terms(const Vec3L<F>& l, const Vec3L<F>& v) {
  // u = l + v, t = |u|² (h = u / √t). Where u nearly vanishes (t below kMinHalfLength2: l
  // and v within 0.06° of opposite) h is undetermined; there t is raised and n·h taken as 0
  // (ggx_DV), which keeps the terms finite and shows no highlight.
  HalfTerms<F> h;
  h.u = l + v;
  h.t_raw = simd::dot(h.u, h.u);
  h.t = simd::max(h.t_raw, F(kMinHalfLength2));
  const F VoH = simd::min(VoH_from_t(h.t), F(1.0f));
  h.m5 = schlick_weight(VoH);
  return h;
}

// D · V of the GGX lobe of normal n for the light of `h`: s = n·u = n·l + n·v and u's part
// across n, u − s n. NoL = n·l clamped to [0, 1], NoV = n·v clamped to [kMinNoV, 1].
template <class F>
inline F ggx_DV(const HalfTerms<F>& h, const Vec3L<F>& n, F n_dot_l, F n_dot_v, F NoL, F NoV, F alpha, F alpha2, F k) {
  const F s = n_dot_l + n_dot_v;
  const Vec3L<F> u_across = h.u - n * s;
  const F dt = simd::select(simd::both(s > F(0.0f), h.t_raw >= F(kMinHalfLength2)),
                            D_GGX_denominator_t(s, u_across, alpha2), h.t);
  return DV_GGX_SchlickSmith_t(dt, h.t, NoL, NoV, alpha, k);
}

template <class F>
inline Vec3L<F> brdf_times(const MaterialLanes<F>& m, const MaterialTerms<F>& mt, const ViewTerms<F>& vt,
                           const Vec3L<F>& n, const Vec3L<F>& l, const Vec3L<F>& v, F w) {
  const F one(1.0f);
  const F n_dot_l = simd::dot(n, l);
  const F NoL = simd::clamp(n_dot_l, F(0.0f), one);
  const HalfTerms<F> h = half_terms(l, v);
  const F specular = ggx_DV(h, n, n_dot_l, vt.n_dot_v, NoL, vt.NoV, m.alpha, mt.alpha2, m.k) * w;
  const F diffuse = (one - h.m5) * w;
  const Vec3L<F> Fr = m.f0 + mt.one_minus_f0 * h.m5;
  return mt.diffuse * diffuse + Fr * specular;
}

// The BRDF f(l, v) alone.
template <class F>
inline Vec3L<F> brdf(const MaterialLanes<F>& m, const Vec3L<F>& n, const Vec3L<F>& l, const Vec3L<F>& v) {
  return brdf_times(m, material_terms(m), view_terms(n, v), n, l, v, F(1.0f));
}

// The light of an environment (split sum, Karis 2013) reflected at unit normal n toward
// unit v: diffuse irradiance(n) and specular prefiltered(r, roughness) · (kS·A + B), with
// r = reflect(−v, n) bent toward n by the lobe's width (its dominant direction), kS = F0 + (max(1 − roughness, F0) − F0)(1 − n·v)⁵ (Fresnel with
// roughness) and (A, B) = dfg_table(n·v, roughness). With multiple scattering (Fdez-Agüera
// 2019): Ess = A + B, Ems = 1 − Ess, Favg = F0 + (1 − F0)/21,
//   specular  = prefiltered · FssEss,   FssEss = kS·A + B
//   diffuse   = irradiance · (FmsEms + c_diff · (1 − FssEss − FmsEms)),
//               FmsEms = Ems · FssEss · Favg / (1 − Favg · Ems),  c_diff = base · (1 − metallic)
// without it: diffuse = irradiance · (1 − kS)(1 − metallic) · base. Both times ao. With
// `occlusion` (the screen-space ambient occlusion of the lanes' pixels, env_occlusion) the
// diffuse term is also multiplied by it and the specular by 1 − e.specular_occlusion·(1 − it)
// (Lagarde & de Rousiers 2014's specular occlusion needs a per-lane pow; docs/design.md).
// Without it the operations are those of a scene without occlusion, bit for bit.
//
// With the material extensions (kLayered, `dielectric` given: layered_shading.h) the
// dielectric's F0 is dielectric->f0 (KHR_materials_ior and _specular) and its specular
// weight w = dielectric->weight scales its F0 and F90, as the glTF Sample Viewer's
// getIBLGGXFresnel does: Fresnel with roughness F0 + (max((1 − roughness) F90, F0) − F0) c⁵,
// FssEss = ks A + F90 B, Favg = F0 + (F90 − F0)/21, where F0 and F90 are the mixed
// material's (m.f0 and dielectric->f90 = w + (1 − w) metallic) for the specular, the
// dielectric's (w · F0, w) for the diffuse weight. At w = 1 and F0 = 0.04 every added
// operation is a multiply by 1: the same bits as the core material's.
//
// Two more layers change only inputs here: an anisotropic lobe (KHR_materials_anisotropy)
// reads the prefiltered map about `specular_normal` (the bent normal, layered_shading.h)
// instead of n when `bent`; a thin film (KHR_materials_iridescence) mixes the reflected
// fractions with its Fresnel by its factor k, as the glTF Sample Viewer does:
// FssEss' = mix(FssEss, F_film, k), the multiple scattering's FmsEms (1 − k), and the
// diffuse lobe's 1 − mix(Fss_d + Fms_d, F_film_d, k).
template <class F>
struct DielectricLanes {
  Vec3L<F> f0;  // the dielectric's F0 times its weight w: w · min(F0(ior) · colour, 1)
  F weight;     // w, the dielectric's F90
  F f90;        // the mixed material's F90, w + (1 − w) metallic
  bool bent = false;          // uniform: the specular lookup about specular_normal
  Vec3L<F> specular_normal;   // unit
  bool film = false;          // uniform: the thin film's terms below are read
  F film_factor;              // k, in [0, 1]
  Vec3L<F> film_f;            // the film's Fresnel of the mixed material
  Vec3L<F> film_f_d;          // … of the dielectric, times w
};

// The lobe's dominant direction (Lagarde & de Rousiers 2014, Frostbite): the mirror
// direction of v about n bent toward n as the lobe widens, f = (1 − α)(√(1 − α) + α) of the
// way from n to r (r at α = 0, n at α = 1); the lookups take any non-zero length.
template <class F>
inline Vec3L<F> dominant_direction(const Vec3L<F>& n, F n_dot_v, const Vec3L<F>& v, F alpha) {
  const F one(1.0f);
  const Vec3L<F> r0 = n * (n_dot_v + n_dot_v) - v;
  const F s = one - alpha;
  const F f = s * (simd::sqrt(s) + alpha);
  return n + (r0 - n) * f;
}

template <class F, bool kLayered = false>
inline Vec3L<F> ibl(const MaterialLanes<F>& m, const PreparedEnvironment& e, const Vec3L<F>& n, const Vec3L<F>& v,
                    const F* occlusion = nullptr, const DielectricLanes<F>* dielectric = nullptr) {
  const F zero(0.0f), one(1.0f);
  const F n_dot_v = simd::dot(n, v);
  const F NoV = simd::clamp(n_dot_v, F(kMinNoV), one);
  // The lobe's dominant direction about n (or, for an anisotropic lobe, its bent normal).
  Vec3L<F> ns = n;
  F ns_dot_v = n_dot_v;
  if constexpr (kLayered) {
    if (dielectric->bent) ns = dielectric->specular_normal, ns_dot_v = simd::dot(ns, v);
  }
  const Vec3L<F> r = dominant_direction(ns, ns_dot_v, v, m.alpha);
  const EnvVec3<F> irr = env_irradiance(e, to_environment(e, n.x, n.y, n.z));
  const EnvVec3<F> rl = to_environment(e, r.x, r.y, r.z);
  const EnvVec3<F> pre = m.uniform_roughness >= 0.0f ? env_radiance_uniform(e, rl, m.uniform_roughness)
                                                     : env_radiance(e, rl, m.roughness);
  F A, B;
  env_dfg(NoV, m.roughness, A, B);
  const F c = one - NoV, c2 = c * c;
  const F c5 = c2 * c2 * c;
  const F smooth_unweighted = one - m.roughness;
  F smooth = smooth_unweighted, f90B = B;
  if constexpr (kLayered) smooth = smooth_unweighted * dielectric->f90, f90B = B * dielectric->f90;
  const Vec3L<F> ks(m.f0.x + (simd::max(smooth, m.f0.x) - m.f0.x) * c5, m.f0.y + (simd::max(smooth, m.f0.y) - m.f0.y) * c5,
                    m.f0.z + (simd::max(smooth, m.f0.z) - m.f0.z) * c5);
  Vec3L<F> fss_ess = ks * A + Vec3L<F>(f90B);
  // The diffuse lobe is the dielectric layer's (glTF 2.0, Appendix B: material =
  // mix(dielectric_brdf, metal_brdf, metallic), dielectric_brdf = mix(diffuse, specular,
  // F(F0 = 0.04))): what it loses to reflection is the dielectric's F, not the F of the
  // mixed F0 — for metallic 0.83 that is 0.49 of the light left, not 0.96 (ksd, fss_d).
  // The same as before for metallic 0, where the mixed F0 is 0.04.
  if constexpr (kLayered) {
    const F w = dielectric->weight;
    const F smooth_d = smooth_unweighted * w, wB = B * w;
    const Vec3L<F>& f0d = dielectric->f0;
    const Vec3L<F> ksd(f0d.x + (simd::max(smooth_d, f0d.x) - f0d.x) * c5, f0d.y + (simd::max(smooth_d, f0d.y) - f0d.y) * c5,
                       f0d.z + (simd::max(smooth_d, f0d.z) - f0d.z) * c5);
    const Vec3L<F> fss_d = ksd * A + Vec3L<F>(wB);
    Vec3L<F> diffuse;
    // The thin film's mix of what the dielectric reflects, x → x + (F_film_d − x) k.
    const auto film_d = [&](const Vec3L<F>& x) {
      return dielectric->film ? x + (dielectric->film_f_d - x) * dielectric->film_factor : x;
    };
    const Vec3L<F> fss_ess_single = fss_ess;
    if (dielectric->film) fss_ess = fss_ess + (dielectric->film_f - fss_ess) * dielectric->film_factor;
    if (e.multiscatter) {
      const F ems = one - (A + B);
      const F f90 = dielectric->f90;
      const Vec3L<F> favg = m.f0 + (Vec3L<F>(f90) - m.f0) * F(1.0f / 21.0f);
      const F floor(1e-3f);
      const Vec3L<F> fe = favg * ems;
      const Vec3L<F>& fs = fss_ess_single;
      Vec3L<F> fms_ems(fs.x * fe.x / simd::max(one - fe.x, floor), fs.y * fe.y / simd::max(one - fe.y, floor),
                       fs.z * fe.z / simd::max(one - fe.z, floor));
      if (dielectric->film) fms_ems = fms_ems * (one - dielectric->film_factor);
      const Vec3L<F> fe_d = (f0d + (Vec3L<F>(w) - f0d) * F(1.0f / 21.0f)) * ems;
      const Vec3L<F> fms_d(fss_d.x * fe_d.x / simd::max(one - fe_d.x, floor), fss_d.y * fe_d.y / simd::max(one - fe_d.y, floor),
                           fss_d.z * fe_d.z / simd::max(one - fe_d.z, floor));
      const Vec3L<F> left = Vec3L<F>(one) - film_d(fss_d + fms_d);
      diffuse = fms_ems + m.albedo * m.one_minus_metallic *
                              Vec3L<F>(simd::max(left.x, zero), simd::max(left.y, zero), simd::max(left.z, zero));
    } else {
      const Vec3L<F> left = Vec3L<F>(one) - film_d(ksd);
      diffuse = Vec3L<F>(simd::max(left.x, zero), simd::max(left.y, zero), simd::max(left.z, zero)) *
                m.one_minus_metallic * m.albedo;
    }
    const Vec3L<F> diffuse_light = Vec3L<F>(irr.x, irr.y, irr.z) * diffuse;
    const Vec3L<F> specular_light = Vec3L<F>(pre.x, pre.y, pre.z) * fss_ess;
    if (occlusion == nullptr) return (diffuse_light + specular_light) * m.ao;
    const F so = one - (one - *occlusion) * F(e.specular_occlusion);
    return (diffuse_light * *occlusion + specular_light * so) * m.ao;
  }
  const F f0d(kDielectricF0);
  const F ksd = f0d + (simd::max(smooth, f0d) - f0d) * c5;
  const F fss_d = ksd * A + B;
  Vec3L<F> diffuse;
  if (e.multiscatter) {
    const F ems = one - (A + B);
    const Vec3L<F> favg = m.f0 + (Vec3L<F>(one) - m.f0) * F(1.0f / 21.0f);
    // 1 − Favg·Ems stays positive for F0 ≤ 1 (Ems < 1); the floor keeps a base colour
    // above 1 (accepted, see prepare_material) finite.
    const F floor(1e-3f);
    const Vec3L<F> fe = favg * ems;
    const Vec3L<F> fms_ems(fss_ess.x * fe.x / simd::max(one - fe.x, floor), fss_ess.y * fe.y / simd::max(one - fe.y, floor),
                           fss_ess.z * fe.z / simd::max(one - fe.z, floor));
    const F fe_d = F(kDielectricF0 + (1.0f - kDielectricF0) * (1.0f / 21.0f)) * ems;
    const F fms_d = fss_d * fe_d / simd::max(one - fe_d, floor);
    diffuse = fms_ems + m.albedo * m.one_minus_metallic * simd::max(one - (fss_d + fms_d), zero);
  } else {
    diffuse = Vec3L<F>(simd::max(one - ksd, zero)) * m.one_minus_metallic * m.albedo;
  }
  const Vec3L<F> diffuse_light = Vec3L<F>(irr.x, irr.y, irr.z) * diffuse;
  const Vec3L<F> specular_light = Vec3L<F>(pre.x, pre.y, pre.z) * fss_ess;
  if (occlusion == nullptr) return (diffuse_light + specular_light) * m.ao;
  const F so = one - (one - *occlusion) * F(e.specular_occlusion);
  return (diffuse_light * *occlusion + specular_light * so) * m.ao;
}

// Outgoing radiance at `position` with normal n (need not be unit) and unit direction to
// the eye v: the reflectance equation over all lights, plus emission, plus the
// environment's light (ibl) when `env` is given and the constant ambient otherwise. Lights
// with n·l ≤ 0 add nothing. This form takes the material's per-draw parts ready:
// mt = material_terms(m) and ambient_ao = ambient · c · ao (read without an environment).
template <class F>
inline Vec3L<F> shade(const MaterialLanes<F>& m, const MaterialTerms<F>& mt, const Vec3L<F>& ambient_ao,
                      std::span<const PreparedLight> lights, const Vec3L<F>& position, const Vec3L<F>& n_in,
                      const Vec3L<F>& v, const PreparedEnvironment* env = nullptr, const F* occlusion = nullptr) {
  const Vec3L<F> n = normalize_or(n_in, v);
  const ViewTerms<F> vt = view_terms(n, v);
  Vec3L<F> lo(F(0.0f));
  // The lights are sampled first, a batch of them, then shaded. A light's dependency chain
  // is long (its distance, that square root and its reciprocal, then n·l, |l + v| and its
  // square root, the D · V division), and a core overlaps two lights only as far as its
  // reorder window reaches. Split in two loops, the sampling of every light overlaps and
  // each shading chain starts from a direction already computed: 0.95x the fill scene's
  // time for 6% more instructions (docs/design.md). The same operations either way.
  constexpr std::size_t kBatch = 8;
  LightSampleLanes<F> samples[kBatch];
  for (std::size_t first = 0; first < lights.size(); first += kBatch) {
    const std::size_t count = std::min(kBatch, lights.size() - first);
    for (std::size_t i = 0; i < count; ++i) samples[i] = sample_light(lights[first + i], position);
    for (std::size_t i = 0; i < count; ++i) {
      const LightSampleLanes<F>& s = samples[i];
      const F NoL = simd::dot(n, s.to_light);
      const auto lit = NoL > F(0.0f);
      if (!simd::any(lit)) continue;
      // A light with a shadow map: the falloff times the part of it that reaches the point.
      if (const ShadowMap* map = lights[first + i].shadow; map != nullptr)
        samples[i].falloff = samples[i].falloff * shadow_visibility(*map, position, n, s.to_light, NoL);
      // f · NoL · falloff, times the light's unattenuated radiance (uniform).
      // The material's lanes are read in the loop, not copied before it (simd::in_memory).
      const Vec3L<F> f =
          brdf_times(*simd::in_memory(&m), *simd::in_memory(&mt), vt, n, s.to_light, v, NoL * s.falloff);
      lo = simd::select(lit, lo + f * lanes<F>(lights[first + i].radiance), lo);
    }
  }
  if (env != nullptr) return ibl(m, *env, n, v, occlusion) + lo + m.emissive;
  return ambient_ao + lo + m.emissive;
}

// ambient · c · ao, the constant ambient's light.
template <class F>
inline Vec3L<F> ambient_light(const MaterialLanes<F>& m, const glm::vec3& ambient) {
  return lanes<F>(ambient) * m.albedo * m.ao;
}

template <class F>
inline Vec3L<F> shade(const MaterialLanes<F>& m, std::span<const PreparedLight> lights, const glm::vec3& ambient,
                      const Vec3L<F>& position, const Vec3L<F>& n_in, const Vec3L<F>& v,
                      const PreparedEnvironment* env = nullptr, const F* occlusion = nullptr) {
  return shade(m, material_terms(m), ambient_light(m, ambient), lights, position, n_in, v, env, occlusion);
}

template <class F>
inline Vec3L<F> brdf(const ShadingMaterial& m, const Vec3L<F>& n, const Vec3L<F>& l, const Vec3L<F>& v) {
  return brdf(lanes<F>(m), n, l, v);
}
template <class F>
inline Vec3L<F> shade(const ShadingMaterial& m, std::span<const PreparedLight> lights, const glm::vec3& ambient,
                      const Vec3L<F>& position, const Vec3L<F>& n_in, const Vec3L<F>& v,
                      const PreparedEnvironment* env = nullptr) {
  return shade(lanes<F>(m), lights, ambient, position, n_in, v, env);
}

// --- The same for one point with glm vectors. ---

inline glm::vec3 to_glm(const Vec3L<float>& v) { return {v.x, v.y, v.z}; }

inline glm::vec3 normalize_or(const glm::vec3& v, const glm::vec3& fallback) {
  return to_glm(normalize_or(lanes<float>(v), lanes<float>(fallback)));
}

inline glm::vec3 brdf(const ShadingMaterial& m, const glm::vec3& n, const glm::vec3& l, const glm::vec3& v) {
  return to_glm(brdf(m, lanes<float>(n), lanes<float>(l), lanes<float>(v)));
}

inline glm::vec3 shade(const ShadingMaterial& m, std::span<const PreparedLight> lights, const glm::vec3& ambient,
                       const glm::vec3& position, const glm::vec3& n, const glm::vec3& v,
                       const PreparedEnvironment* env = nullptr) {
  return to_glm(shade(m, lights, ambient, lanes<float>(position), lanes<float>(n), lanes<float>(v), env));
}

// The PBR shader for softpbr::raster: world-space position and normal as varyings, the
// reflectance equation per pixel. Alpha is 1.
struct PbrShader {
  using Vertex = MeshVertex;
  // Only what the equation reads: the mesh's uv is not passed on (no textures yet; each
  // varying costs memory per vertex and work per pixel).
  struct Varyings {
    glm::vec3 world_position;
    glm::vec3 normal;
  };
  // No texture lookups, so no derivatives: helper lanes of a quad are not interpolated.
  static constexpr bool kUsesDerivatives = false;

  glm::mat4 model{1.0f};
  glm::mat3 normal_matrix{1.0f};  // inverse transpose of model's upper 3×3
  glm::mat4 view_projection{1.0f};
  glm::vec3 eye{0.0f};
  // An orthographic camera: every point is seen from `view_direction` (unit, towards the
  // camera) instead of from `eye`.
  bool orthographic = false;
  glm::vec3 view_direction{0.0f, 0.0f, 1.0f};
  glm::vec3 ambient{0.0f};
  ShadingMaterial material{};
  std::shared_ptr<const std::vector<PreparedLight>> lights;
  // The environment's light instead of `ambient`, when set (it outlives the frame).
  const PreparedEnvironment* environment = nullptr;

  glm::vec4 vertex(const Vertex& in, Varyings& out) const {
    const glm::vec4 world = model * glm::vec4(in.position, 1.0f);
    out.world_position = glm::vec3(world);
    out.normal = normal_matrix * in.normal;
    return view_projection * world;
  }
  // One pixel.
  glm::vec4 fragment(const raster::Fragment<Varyings>& f) const {
    const glm::vec3 v =
        orthographic ? view_direction : normalize_or(eye - f.v.world_position, glm::vec3(0.0f, 0.0f, 1.0f));
    if (environment != nullptr && environment->occlusion != nullptr) {
      const float o = env_occlusion(*environment, f.pos.x, f.pos.y);
      const Vec3L<float> c = shade(lanes<float>(material), *lights, ambient, lanes<float>(f.v.world_position),
                                   lanes<float>(f.v.normal), lanes<float>(v), environment, &o);
      return glm::vec4(c.x, c.y, c.z, 1.0f);
    }
    const glm::vec3 color = shade(material, *lights, ambient, f.v.world_position, f.v.normal, v, environment);
    return glm::vec4(color, 1.0f);
  }

  // What every packet of a draw reads, in lanes: built once per draw and tile by the
  // renderer (raster/shader.h, packet_uniforms), not re-derived per packet.
  template <class F>
  struct PacketUniforms {
    MaterialLanes<F> material;
    MaterialTerms<F> terms;
    Vec3L<F> ambient_ao;  // ambient · c · ao
    Vec3L<F> eye;
    Vec3L<F> view_direction;
  };
  template <class F>
  PacketUniforms<F> packet_uniforms() const {
    PacketUniforms<F> u;
    u.material = lanes<F>(material);
    u.terms = material_terms(u.material);
    u.ambient_ao = ambient_light(u.material, ambient);
    u.eye = lanes<F>(eye);
    u.view_direction = lanes<F>(view_direction);
    return u;
  }

  // Lanes of pixels: the same code per lane.
  template <class F>
  raster::Color<F> fragment_packet(const raster::FragmentPacket<F, Varyings>& p, const PacketUniforms<F>& u) const {
    constexpr int kPosition = offsetof(Varyings, world_position) / sizeof(float);
    constexpr int kNormal = offsetof(Varyings, normal) / sizeof(float);
    const Vec3L<F> position(p.v[kPosition], p.v[kPosition + 1], p.v[kPosition + 2]);
    const Vec3L<F> normal(p.v[kNormal], p.v[kNormal + 1], p.v[kNormal + 2]);
    const Vec3L<F> v =
        orthographic ? u.view_direction : normalize_or(u.eye - position, Vec3L<F>(F(0.0f), F(0.0f), F(1.0f)));
    if (environment != nullptr && environment->occlusion != nullptr) {
      const F o = env_occlusion(*environment, p.pos_x, p.pos_y);
      const Vec3L<F> c = shade(u.material, u.terms, u.ambient_ao, *lights, position, normal, v, environment, &o);
      return {c.x, c.y, c.z, F(1.0f)};
    }
    const Vec3L<F> c = shade(u.material, u.terms, u.ambient_ao, *lights, position, normal, v, environment);
    return {c.x, c.y, c.z, F(1.0f)};
  }
  template <class F>
  raster::Color<F> fragment_packet(const raster::FragmentPacket<F, Varyings>& p) const {
    return fragment_packet(p, packet_uniforms<F>());
  }
};

}  // namespace softpbr::pbr
