// softpbr/pbr/layered_shading.h — the reflectance equation with glTF's material extensions:
// KHR_materials_ior and _specular (the dielectric's F0 and F90), _sheen and _clearcoat,
// _anisotropy, _iridescence, _transmission, _volume and _dispersion.
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
// The transmission (KHR_materials_transmission, _volume; the glTF Sample Viewer's screen-space
// technique, as three.js and Filament): the diffuse lobe becomes mix(f_diffuse, f_transmission, T),
//   f_transmission = (1 − (F0_d A + w B)) · c (1 − metallic) · ao · τ · L_behind
// with L_behind what the opaque pass left on screen where the refracted ray leaves the
// volume (TransmissionSource: its mip chain read at LOD levels · roughness · clamp(2 ior − 2,
// 0, 1)), the environment along the refracted ray where that point is off screen, and
// τ = exp(−σ d) per channel over the ray's length d in the volume (Beer–Lambert).
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

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "softpbr/pbr/brdf.h"
#include "softpbr/pbr/environment_lookup.h"
#include "softpbr/pbr/lane_math.h"
#include "softpbr/pbr/shading.h"
#include "softpbr/raster/texture.h"

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

template <class F>
struct AnisotropyLanes {
  F strength;  // in [0, 1]
  Vec3L<F> t;  // unit: the direction of increased roughness, in the surface's plane
  Vec3L<F> b;  // unit: across it, n_geometric × t
};

template <class F>
struct FilmLanes {
  F factor;     // in [0, 1]
  F thickness;  // nanometres
  float ior;    // the film's index (uniform)
};

template <class F>
struct TransmissionLanes {
  F factor;     // T, in [0, 1]
  F thickness;  // the volume's thickness, in the mesh's units (≥ 0)
  F roughness;  // the base's perceptual roughness before kMinRoughness, in [0, 1]
};

// What the transmissive draws of a frame see behind them: the opaque pass's resolved
// linear colour (render(): the opaque objects and the background) as a float texture with
// its mip chain, read through a clamp-to-edge trilinear sampler.
struct TransmissionSource {
  const raster::Texture* texture = nullptr;  // null: nothing on screen (the environment only)
  raster::Sampler sampler;
  float levels = 0.0f;  // log₂ of the texture's larger side: the LOD of roughness 1
};

// A transmissive draw's uniforms: the frame's source, the projection that finds a point on
// it, the object's scale (the thickness is in the mesh's units: glTF scales it by the node's
// scale, the lengths of the model matrix's columns, as the Sample Viewer does), and the
// material's refraction and attenuation (PreparedLayers).
struct TransmissionUniforms {
  const TransmissionSource* source = nullptr;
  glm::mat4 view_projection{1.0f};
  glm::vec3 scale{1.0f};
  float eta = 1.0f / 1.5f;    // 1 / ior (0 for an ior of 0, i.e. +∞)
  float lod_scale = 0.0f;     // clamp(2 ior − 2, 0, 1): an ior of 1 refracts without blur
  bool attenuated = false;    // a finite attenuation distance
  glm::vec3 sigma{0.0f};      // −ln(attenuation colour) / attenuation distance, ≤ kMaxSigma
  bool dispersed = false;     // KHR_materials_dispersion above 0: a ray per channel
  glm::vec3 eta_rgb{1.0f / 1.5f}, lod_scale_rgb{0.0f};  // eta and lod_scale per channel
};
inline constexpr float kMaxSigma = 1e30f;  // a black attenuation colour: σ finite, so σ · 0 = 0

// The layers of a material per lane. `coat`, `sheen`, `anisotropy` and `film` say whether
// the layer is on for the draw (uniform); their lanes are read only then.
template <class F>
struct LayerLanes {
  DielectricLanes<F> dielectric;
  bool coat = false;
  bool sheen = false;
  bool anisotropy = false;
  bool film = false;
  bool transmission = false;
  CoatLanes<F> coat_lanes;
  SheenLanes<F> sheen_lanes;
  AnisotropyLanes<F> anisotropy_lanes;
  FilmLanes<F> film_lanes;
  TransmissionLanes<F> transmission_lanes;
  const TransmissionUniforms* transmission_uniforms = nullptr;  // with `transmission`
  Vec3L<F> dielectric_color;  // min(F0(ior) · specular colour, 1), unweighted (the film's base)
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
  const Vec3L<F> r = dominant_direction(n, n_dot_v, v, alpha);
  const EnvVec3<F> pre = env_radiance(e, to_environment(e, r.x, r.y, r.z), roughness);
  return {pre.x, pre.y, pre.z};
}

// The normal about which an anisotropic lobe's image-based light is looked up (the glTF
// Sample Viewer's and Filament's bent normal, after Revie 2012): the normal of the plane
// through b and v, n_a = (b × v) × b, mixed toward n by (1 − strength (1 − roughness))⁴:
// n at strength 0, the stretched reflection's plane at strength 1 on a smooth surface.
template <class F>
inline Vec3L<F> bent_normal(const AnisotropyLanes<F>& an, const Vec3L<F>& n, const Vec3L<F>& v, F roughness) {
  const F one(1.0f);
  const auto cross = [](const Vec3L<F>& a, const Vec3L<F>& b) {
    return Vec3L<F>(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
  };
  const Vec3L<F> na = cross(cross(an.b, v), an.b);
  const F bend = one - an.strength * (one - roughness);
  const F bend2 = bend * bend;
  return normalize_or(na + (n - na) * (bend2 * bend2), n);
}

// The largest of a colour's three channels.
template <class F>
inline F max3(const Vec3L<F>& c) {
  return simd::max(simd::max(c.x, c.y), c.z);
}

// The radiance seen through a transmissive surface at `position` (unit normal n, unit v,
// n_dot_v = n·v): the refracted direction refract(−v, n, 1/ior) as GLSL's refract, the
// point it leaves the volume, position + dir · thickness · scale, projected onto the
// source (u = (x/w + 1)/2, v = (1 − y/w)/2: row 0 at the top) and read at LOD
// source.levels · roughness · lod_scale; where that point is off screen (or behind the
// eye), the environment's prefiltered radiance along dir at the same roughness when there
// is one; then τ = exp(−σ d) per channel, d the distance travelled (Beer–Lambert; exp_lanes).
// With dispersion (KHR_materials_dispersion) each channel is read along its own ray, of
// index ior ∓ (ior − 1) · 0.025 · dispersion for red and blue (the Sample Viewer's), and d
// is the green ray's.
template <class F>
inline Vec3L<F> transmitted_light(const TransmissionUniforms& t, const TransmissionLanes<F>& tl,
                                  const Vec3L<F>& position, const Vec3L<F>& n, const Vec3L<F>& v, F n_dot_v,
                                  const PreparedEnvironment* env) {
  const F zero(0.0f), one(1.0f), half(0.5f);
  // refract(I = −v, n, η) = η I − (η (n·I) + √k) n, k = 1 − η² (1 − (n·I)²); η ≤ 1, so k ≥ 1 − η² ≥ 0.
  const auto refracted = [&](float eta_uniform, Vec3L<F>& dir, Vec3L<F>& ray) {
    const F eta(eta_uniform);
    const F k = simd::max(one - eta * eta * (one - n_dot_v * n_dot_v), zero);
    dir = normalize_or(n * (eta * n_dot_v - simd::sqrt(k)) - v * eta, -n);
    ray = Vec3L<F>(dir.x * (tl.thickness * F(t.scale.x)), dir.y * (tl.thickness * F(t.scale.y)),
                   dir.z * (tl.thickness * F(t.scale.z)));
  };
  // What is seen where `ray` leaves the volume: the source there, else the environment along dir.
  const auto seen_along = [&](const Vec3L<F>& dir, const Vec3L<F>& ray, F roughness) {
    const Vec3L<F> exit = position + ray;
    const glm::mat4& m = t.view_projection;
    const F cx = F(m[0][0]) * exit.x + F(m[1][0]) * exit.y + F(m[2][0]) * exit.z + F(m[3][0]);
    const F cy = F(m[0][1]) * exit.x + F(m[1][1]) * exit.y + F(m[2][1]) * exit.z + F(m[3][1]);
    const F cw = F(m[0][3]) * exit.x + F(m[1][3]) * exit.y + F(m[2][3]) * exit.z + F(m[3][3]);
    const auto ahead = cw > zero;
    const F w = simd::select(ahead, cw, one);
    const F u = (cx / w + one) * half;
    const F vv = (one - cy / w) * half;
    const auto inside =
        simd::both(simd::both(ahead, simd::both(u >= zero, u <= one)), simd::both(vv >= zero, vv <= one));
    Vec3L<F> seen(zero);
    if (t.source != nullptr && t.source->texture != nullptr) {
      const raster::Color<F> c = raster::sample_lod(*t.source->texture, t.source->sampler, simd::select(inside, u, half),
                                                    simd::select(inside, vv, half), roughness * F(t.source->levels));
      seen = Vec3L<F>(simd::select(inside, c.r, zero), simd::select(inside, c.g, zero), simd::select(inside, c.b, zero));
    }
    if (env != nullptr && simd::any(simd::select(inside, zero, one) > zero)) {
      const EnvVec3<F> pre = env_radiance(*env, to_environment(*env, dir.x, dir.y, dir.z), roughness);
      seen = Vec3L<F>(simd::select(inside, seen.x, pre.x), simd::select(inside, seen.y, pre.y),
                      simd::select(inside, seen.z, pre.z));
    }
    return seen;
  };
  Vec3L<F> dir, ray, seen;
  if (!t.dispersed) {
    refracted(t.eta, dir, ray);
    seen = seen_along(dir, ray, tl.roughness * F(t.lod_scale));
  } else {
    Vec3L<F> dir_c, ray_c;
    refracted(t.eta_rgb.x, dir_c, ray_c);
    seen.x = seen_along(dir_c, ray_c, tl.roughness * F(t.lod_scale_rgb.x)).x;
    refracted(t.eta_rgb.z, dir_c, ray_c);
    seen.z = seen_along(dir_c, ray_c, tl.roughness * F(t.lod_scale_rgb.z)).z;
    refracted(t.eta_rgb.y, dir, ray);
    seen.y = seen_along(dir, ray, tl.roughness * F(t.lod_scale_rgb.y)).y;
  }
  if (t.attenuated) {
    const F d = simd::sqrt(simd::dot(ray, ray));
    seen = Vec3L<F>(seen.x * exp_lanes(F(-t.sigma.x) * d), seen.y * exp_lanes(F(-t.sigma.y) * d),
                    seen.z * exp_lanes(F(-t.sigma.z) * d));
  }
  return seen;
}

// Outgoing radiance with the layers: shade() (shading.h) of the layered material. m.f0
// must be layered_f0(layers.dielectric, …).
template <class F>
inline Vec3L<F> shade_layered(const MaterialLanes<F>& m_in, const LayerLanes<F>& layers,
                              std::span<const PreparedLight> lights, const glm::vec3& ambient, const Vec3L<F>& position,
                              const Vec3L<F>& n_in, const Vec3L<F>& v, const PreparedEnvironment* env,
                              const std::type_identity_t<F>* occlusion) {
  const F zero(0.0f), one(1.0f);
  // A transmission takes T of the diffuse lobe (mix(f_diffuse, f_transmission, T)): the
  // diffuse terms below read the albedo times 1 − T; the film and the transmitted light
  // read the material's own (m_in).
  MaterialLanes<F> m_t;
  if (layers.transmission) {
    m_t = m_in;
    m_t.albedo = m_in.albedo * (one - layers.transmission_lanes.factor);
  }
  const MaterialLanes<F>& m = layers.transmission ? m_t : m_in;
  DielectricLanes<F> d = layers.dielectric;
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

  // Anisotropy: α_t, α_b and the view's t·v, b·v; the bent normal of the image-based light.
  F at = m.alpha, ab = m.alpha, ToV = zero, BoV = zero;
  if (layers.anisotropy) {
    const AnisotropyLanes<F>& an = layers.anisotropy_lanes;
    at = m.alpha + (one - m.alpha) * (an.strength * an.strength);
    ToV = simd::dot(an.t, v);
    BoV = simd::dot(an.b, v);
    d.bent = true;
    d.specular_normal = bent_normal(an, n, v, m.roughness);
  }
  // The thin film: its Fresnel at n·v over the dielectric (times w) and over the metal, mixed
  // by metallic as F0 is; the diffuse lobe's weight 1 − F_film_d (times c/π (1 − metallic)).
  Vec3L<F> film_diffuse(zero);
  if (layers.film) {
    const FilmLanes<F>& fl = layers.film_lanes;
    const ThinFilm<F> tf = thin_film(vt.NoV, F(fl.ior), fl.thickness);
    const Vec3L<F> fd = F_iridescence(tf, layers.dielectric_color) * d.weight;
    const Vec3L<F> fm = F_iridescence(tf, m_in.albedo);
    d.film = true;
    // A film of thickness 0 is none (as the Sample Viewer and three.js: the formula's
    // Schlick terms do not vanish there).
    d.film_factor = simd::select(fl.thickness > zero, fl.factor, zero);
    d.film_f_d = fd;
    d.film_f = fd + (fm - fd) * (one - m.one_minus_metallic);
    const Vec3L<F> left = Vec3L<F>(one) - fd;
    film_diffuse = m.albedo * Vec3L<F>(simd::max(left.x, zero), simd::max(left.y, zero), simd::max(left.z, zero)) *
                   (m.one_minus_metallic * Fd_Lambert<F>() * d.film_factor);
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
      // A light with a shadow map (as shade()): the falloff times the part that reaches the point.
      if (const ShadowMap* map = lights[first + i].shadow; map != nullptr)
        samples[i].falloff = samples[i].falloff * shadow_visibility(*map, position, n, l, n_dot_l);
      const F NoL = simd::clamp(n_dot_l, zero, one);
      const HalfTerms<F> h = half_terms(l, v);
      const F w = NoL * s.falloff;
      F specular;
      if (layers.anisotropy) {
        const AnisotropyLanes<F>& an = layers.anisotropy_lanes;
        const F ToL = simd::dot(an.t, l), BoL = simd::dot(an.b, l);
        const F s_nu = n_dot_l + vt.n_dot_v;  // n·u
        const F D = simd::select(simd::both(s_nu > zero, h.t_raw >= F(kMinHalfLength2)),
                                 D_GGX_anisotropic_t(ToL + ToV, BoL + BoV, s_nu, h.t, at, ab), zero);
        specular = D * V_GGX_anisotropic(NoL, vt.NoV, ToV, BoV, ToL, BoL, at, ab) * w;
      } else {
        specular = ggx_DV(h, n, n_dot_l, vt.n_dot_v, NoL, vt.NoV, m.alpha, mt.alpha2, m.k) * w;
      }
      const F m5w = h.m5 * w;
      Vec3L<F> Fr = m.f0 + f90_minus_f0 * h.m5;
      Vec3L<F> f;
      if (layers.film) {
        const F k = d.film_factor;
        Fr = Fr + (d.film_f - Fr) * k;
        f = (mt.diffuse * ((one - h.m5) * w) + diffuse_f90 * m5w) * (one - k) + film_diffuse * w + Fr * specular;
      } else {
        f = mt.diffuse * ((one - h.m5) * w) + diffuse_f90 * m5w + Fr * specular;
      }
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
  // The transmitted light, in the diffuse lobe's place (before the sheen and the coat).
  if (layers.transmission) {
    const TransmissionLanes<F>& tl = layers.transmission_lanes;
    F A, B;
    env_dfg(vt.NoV, m.roughness, A, B);
    const Vec3L<F> reflected = d.f0 * A + Vec3L<F>(d.weight * B);
    const Vec3L<F> seen = transmitted_light(*layers.transmission_uniforms, tl, position, n, v, vt.n_dot_v, env);
    indirect = indirect + (Vec3L<F>(one) - reflected) * m_in.albedo * seen *
                              (tl.factor * m_in.one_minus_metallic * m_in.ao);
  }
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
