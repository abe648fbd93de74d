// softpbr/pbr/brdf.h — the terms of the Cook-Torrance microfacet BRDF, one small function each.
//
// Names follow Filament ("Physically Based Rendering in Filament", R. Guy & M. Agopian):
// D_ = normal distribution, G_ = geometric shadowing-masking, V_ = visibility
// G / (4 · NoL · NoV), F_ = Fresnel, Fd_ = diffuse; DV_ = D · V folded into one expression.
// NoH = n·h, NoV = n·v, NoL = n·l, VoH = v·h, all clamped to [0, 1] by the caller.
// α = roughness² (perceptual roughness squared, Burley 2012).
//
// The specular lobe is f_s = D · G · F / (4 · NoL · NoV) = DV · F. Each term is written once
// against a lane type F: float for one pixel, simd::Vec<N> for N pixels (the same IEEE
// operations per lane, simd.h), and, for the textbook terms, double: the shader
// (shading.h brdf_times) evaluates D_GGX_denominator_t, DV_GGX_SchlickSmith_t, VoH_from_t,
// schlick_weight and Fd_Lambert in float lanes; the tests check them (and the n·h forms
// DV_GGX_SchlickSmith, F_Schlick) against D_GGX, G_Smith and F_Schlick in double.
#pragma once

#include <glm/vec3.hpp>

#include "softpbr/pbr/lane_math.h"
#include "softpbr/simd/simd.h"

namespace softpbr::pbr {

inline constexpr float kPi = 3.14159265358979323846f;
inline constexpr float kInvPi = 0.318309886183790671538f;
// The same constants in double for the templates: T(kPiDouble) is exact for double and
// rounds to the very same float as kPi for float (likewise kInvPiDouble and kInvPi).
inline constexpr double kPiDouble = 3.14159265358979323846;
inline constexpr double kInvPiDouble = 0.318309886183790671538;
static_assert(static_cast<float>(kPiDouble) == kPi && static_cast<float>(kInvPiDouble) == kInvPi);

// Smallest n·v used by the specular term (the caller clamps NoV to it), and the floor of
// n·l in DV's divisor: keeps G1(n·v)/(n·v) ≤ 1/k finite at grazing angles and for normals
// facing away.
inline constexpr float kMinNoV = 1e-4f;

// The denominator of D_GGX without π and the square: d = (n·h)²(α² − 1) + 1, from a2 = α².
// ≥ a2 > 0 for NoH in [0, 1]. Precision: in float, a2 − 1 rounds to a multiple of 2⁻²⁴, so
// at kMinRoughness (a2 ≈ 4·10⁻⁶) D's peak 1/(π α²) comes out 0.6% low and ∫ D (n·h) dω
// 0.25% low; 2·10⁻⁴ low at roughness 0.1, less above (tests/test_brdf.cpp).
template <class F>
inline F D_GGX_denominator(F NoH, F a2) {
  return NoH * NoH * (a2 - F(1)) + F(1);
}

// Trowbridge & Reitz 1975 / Walter et al. 2007 ("GGX"): D(h) = α² / (π ((n·h)²(α² − 1) + 1)²).
// Normalised: ∫ D(h) (n·h) dω_h = 1 over the hemisphere.
template <class F>
inline F D_GGX(F NoH, F alpha) {
  const F a2 = alpha * alpha;
  const F d = D_GGX_denominator(NoH, a2);
  return a2 / (F(kPiDouble) * d * d);
}

// The denominator of G_SchlickGGX: g(x) = x (1 − k) + k, so that G1(x) = x / g(x).
template <class F>
inline F G_SchlickGGX_denominator(F NoX, F k) {
  return NoX * (F(1) - k) + k;
}

// Schlick 1994 with Karis 2013's k for direct light, k = (roughness + 1)² / 8:
// G1(x) = x / (x (1 − k) + k). Returns G1, not a visibility term.
template <class F>
inline F G_SchlickGGX(F NoX, F k) {
  return NoX / G_SchlickGGX_denominator(NoX, k);
}

// k of G_SchlickGGX for analytic (direct) lights, from perceptual roughness (Karis 2013,
// "Real Shading in Unreal Engine 4").
template <class F>
inline F k_direct(F roughness) {
  const F r1 = roughness + F(1);
  return r1 * r1 / F(8);
}

// Smith 1967, separable form: G(l, v) = G1(n·v) · G1(n·l). Returns G.
template <class F>
inline F G_Smith(F NoV, F NoL, F k) {
  return G_SchlickGGX(NoV, k) * G_SchlickGGX(NoL, k);
}

// D_GGX · G_Smith / (4 · NoL · NoV) in one division — the distribution times the
// visibility, as the shader evaluates it. Returns D · V, not G. With D = α² / (π d²) and
// G = (NoV / g(NoV)) (NoL / g(NoL)) (d and g the denominators above), NoV cancels:
//   D · G / (4 NoL NoV) = α² NoL / (4π d² g(NoV) g(NoL) NoL),
// and NoL is kept in the numerator with the divisor's NoL floored at kMinNoV, so that a
// light grazing below the floor fades to 0 instead of dividing by ~0 (NoL = 0 gives 0).
// NoV must be ≥ kMinNoV (the caller clamps it). For F = float or simd::Vec<N>.
template <class F>
inline F DV_GGX_SchlickSmith(F NoH, F NoL, F NoV, F alpha, F k) {
  const F a2 = alpha * alpha;
  const F d = D_GGX_denominator(NoH, a2);
  const F g_v = G_SchlickGGX_denominator(NoV, k), g_l = G_SchlickGGX_denominator(NoL, k);
  return (a2 * NoL) / (F(4.0f * kPi) * d * d * g_v * g_l * simd::max(NoL, F(kMinNoV)));
}

// The same D · V without forming h — the shader's form. With u = l + v, t = |u|² and
// s = n·u, for unit n: h = u / √t, n·h = s / √t, and D_GGX_denominator times t is
//   d t = ((n·h)² (α² − 1) + 1) t = s² α² + (t − s²) = s² α² + |n × u|²
// by Lagrange's identity (|n|² |u|² = (n·u)² + |n × u|²). A sum of two non-negative terms,
// each rounded relative to itself: near a highlight's peak, where (n·h)² (α² − 1) + 1
// cancels to ≈ α² and its float form kept only a few bits there (α² − 1 alone rounds to a
// multiple of 2⁻²⁴, and a float n·h's rounding is squared into it: at roughness 0.045 the
// peak's D·V was up to 11% off, tests/test_brdf.cpp), this keeps ~2⁻²² relative. Where h
// dips below the surface (s < 0) the caller takes n·h = 0, d t = t, as the clamped form
// did. `u_across` is u's part across n, of squared length |n × u|²: the
// shader passes u − s n (three multiplies and subtractions, where n × u takes six and
// three); at a peak (u along n) both are differences of nearly equal numbers with errors
// of a few ulps of |u|, far below s² α².
template <class F>
inline F D_GGX_denominator_t(F s, const simd::Vec3<F>& u_across, F a2) {
  return s * s * a2 + simd::dot(u_across, u_across);
}

// D · V from d t (above) and t: with D = α² / (π d²), DV_GGX_SchlickSmith becomes
//   D · V = α² NoL t² / (4π (d t)² g(NoV) g(NoL) max(NoL, kMinNoV)),
// one division, and n·h costs no square root or division (h normalized, n·h and v·h were
// one root and two divisions a light). Requires t ≥ kMinHalfLength2 (the caller raises a
// smaller t: l ≈ −v, where h is undetermined), d t ≥ α² t (true of the form above) and
// NoV ≥ kMinNoV; then nothing underflows (d t ≥ 10⁻⁶ α² ≥ 4·10⁻¹²) or overflows.
inline constexpr float kMinHalfLength2 = 1e-6f;
template <class F>
inline F DV_GGX_SchlickSmith_t(F dt, F t, F NoL, F NoV, F alpha, F k) {
  const F a2 = alpha * alpha;
  const F g_v = G_SchlickGGX_denominator(NoV, k), g_l = G_SchlickGGX_denominator(NoL, k);
  return (a2 * NoL * (t * t)) / (F(4.0f * kPi) * dt * dt * g_v * g_l * simd::max(NoL, F(kMinNoV)));
}

// v·h from t = |l + v|² = 2 (1 + v·l) as above: (1 + v·l) / √t = √t / 2. One square
// root, no division.
template <class F>
inline F VoH_from_t(F t) {
  return simd::sqrt(t) * F(0.5f);
}

// m⁵ of Schlick's Fresnel, m = 1 − v·h: F = F0 + (1 − F0) m⁵, and the diffuse weight's
// 1 − F = (1 − F0)(1 − m⁵), so both come from m⁵ and the per-pixel (1 − F0). Multiplies
// only, no pow.
template <class F>
inline F schlick_weight(F VoH) {
  const F m = F(1) - VoH;
  const F m2 = m * m;
  return m2 * m2 * m;
}

// Schlick 1994: F = F0 + (1 − F0)(1 − v·h)^5; the fifth power as multiplies, exact and
// deterministic (no pow). One colour per lane of VoH.
template <class F>
inline simd::Vec3<F> F_Schlick(const simd::Vec3<F>& f0, F VoH) {
  const F m = F(1) - VoH;
  const F m2 = m * m;
  const F m5 = m2 * m2 * m;
  return f0 + (simd::Vec3<F>(F(1)) - f0) * m5;
}

// Lambert: a perfectly diffuse surface reflects c/π in every direction. Returns the BRDF
// without the albedo: multiply by c.
template <class F>
inline F Fd_Lambert() {
  return F(kInvPiDouble);
}

// F0 of a dielectric in the metal/roughness model (glTF: ior 1.5).
inline constexpr float kDielectricF0 = 0.04f;

// F0 of a dielectric of index of refraction `ior` in air (Fresnel at normal incidence):
// ((ior − 1) / (ior + 1))², in double, rounded once: exactly kDielectricF0 at 1.5. 0 and
// +∞ give 1, as KHR_materials_ior allows for "F0 from the specular colour alone".
inline float f0_from_ior(double ior) {
  if (ior == 0.0 || ior > 1e30) return 1.0f;
  const double r = (ior - 1.0) / (ior + 1.0);
  return static_cast<float>(r * r);
}

// --- The sheen layer (KHR_materials_sheen): Estevez & Kulla 2017, "Production Friendly
// Microfacet Sheen BRDF" ("Charlie"), with α = sheen roughness² as the glTF Sample Viewer
// and Filament take it. Written against F (lanes, or double for the tables and the tests),
// with lane_math.h's pow and exp. ---

// The smallest sheen roughness shaded: α = 0.002 keeps D_Charlie's exponent 1/(2α) ≤ 250
// and its peak (2 + 1/α)/(2π) ≤ 80 (the specification's roughness 0 has no finite D).
inline constexpr float kMinSheenRoughness = 0.045f;

// D(h) = (2 + 1/α) sin(θ_h)^(1/α) / (2π), from sin²θ_h: (sin²θ_h)^(1/(2α)). Normalised:
// ∫ D (n·h) dω_h = 1. sin²θ_h = 1 − (n·h)², or, without cancellation, |n × h|².
template <class F>
inline F D_Charlie(F sin2h, F alpha) {
  const F inv = F(1.0) / alpha;
  return (F(2.0) + inv) * pow_lanes(sin2h, inv * F(0.5)) * F(0.5 * kInvPiDouble);
}

// The exponent's fit l(x) of the Charlie visibility (Estevez & Kulla 2017, eq. 3, its
// table's two rows blended by (1 − α)²): a / (1 + b x^c) + d x + e.
template <class F>
inline F sheen_l(F x, F alpha) {
  const F t = (F(1.0) - alpha) * (F(1.0) - alpha);
  const F a = F(21.5473) + (F(25.3245) - F(21.5473)) * t;
  const F b = F(3.82987) + (F(3.32435) - F(3.82987)) * t;
  const F c = F(0.19823) + (F(0.16801) - F(0.19823)) * t;
  const F d = F(-1.97760) + (F(-1.27393) - F(-1.97760)) * t;
  const F e = F(-4.32054) + (F(-4.85967) - F(-4.32054)) * t;
  return a / (F(1.0) + b * pow_lanes(x, c)) + d * x + e;
}

// Λ(cos θ) of the Charlie visibility: e^l(cos θ) below cos θ = 1/2, e^(2 l(1/2) − l(1 − cos θ))
// above (the fit mirrored, as the paper's "terminator softening" prescribes). `l_half` is
// sheen_l(1/2, α), the same for every light of a pixel. One pow and one exp per call.
template <class F>
inline F lambda_sheen(F cos_theta, F alpha, F l_half) {
  const auto low = cos_theta < F(0.5);
  const F l = sheen_l(simd::select(low, cos_theta, F(1.0) - cos_theta), alpha);
  return exp_lanes(simd::select(low, l, l_half + l_half - l));
}

// The Charlie visibility times n·l: V (n·l) = n·l / ((1 + Λ(n·v) + Λ(n·l)) 4 (n·l)(n·v))
// = 1 / ((1 + Λ(n·v) + Λ(n·l)) 4 n·v), n·v ≥ kMinNoV (the caller clamps), with V at most
// 1 (as the glTF Sample Viewer clamps it): at most n·l.
template <class F>
inline F V_Charlie_times_NoL(F lambda_v, F lambda_l, F NoV, F NoL) {
  return simd::min(F(1.0) / ((F(1.0) + lambda_v + lambda_l) * F(4.0) * NoV), NoL);
}

// --- Anisotropy (KHR_materials_anisotropy; Burley 2012, Heitz 2014, the extension's
// formulas): GGX with roughness α_t along the unit direction t of the surface and α_b along
// b = n × t, α_t = mix(α, 1, strength²), α_b = α. ---

// D(h) = 1 / (π α_t α_b ((t·h / α_t)² + (b·h / α_b)² + (n·h)²)²), written as the extension
// writes it: a² = α_t α_b, f = (α_b t·h, α_t b·h, a² n·h), w² = a² / f·f, D = a² w⁴ / π.
// From u = l + v unnormalised (t·u, b·u, n·u and t = |u|²: h = u / √t), w² = a² t / f_u·f_u.
// w² is capped at 1/a², its largest value for an orthonormal frame, so a frame that is not
// (a normal map's n against the surface's t and b) keeps D ≤ 1/(π a²) finite. Normalised:
// ∫ D (n·h) dω_h = 1 (tests/test_layers.cpp). At α_t = α_b = α it is D_GGX.
template <class F>
inline F D_GGX_anisotropic_t(F ToU, F BoU, F NoU, F t, F at, F ab) {
  const F a2 = at * ab;
  const F fx = ab * ToU, fy = at * BoU, fz = a2 * NoU;
  const F ff = simd::max(fx * fx + fy * fy + fz * fz, F(1e-30));
  const F w2 = simd::min(a2 * t / ff, F(1.0) / a2);
  return a2 * w2 * w2 * F(kInvPiDouble);
}

// The height-correlated Smith visibility G₂ / (4 (n·l)(n·v)) with the anisotropic Λ
// (Heitz 2014, eq. 99): 1/2 / (n·l |(α_t t·v, α_b b·v, n·v)| + n·v |(α_t t·l, α_b b·l, n·l)|),
// at most 1 (as the extension's reference clamps it). At α_t = α_b = α it is the isotropic
// height-correlated V_SmithGGXCorrelated. NoV ≥ kMinNoV keeps the divisor positive.
template <class F>
inline F V_GGX_anisotropic(F NoL, F NoV, F ToV, F BoV, F ToL, F BoL, F at, F ab) {
  const F tv = at * ToV, bv = ab * BoV, tl = at * ToL, bl = ab * BoL;
  const F lv = simd::sqrt(tv * tv + bv * bv + NoV * NoV);
  const F ll = simd::sqrt(tl * tl + bl * bl + NoL * NoL);
  return simd::min(F(0.5) / simd::max(NoL * lv + NoV * ll, F(1e-30)), F(1.0));
}

// --- The thin film (KHR_materials_iridescence; Belcour & Barla 2017, "A Practical
// Extension to Microfacet Theory for the Modeling of Varying Iridescence", as the
// extension's implementation notes give it): the Fresnel reflectance of a film of index η₂
// and thickness d (nm) in air over a base of F0, with the interference summed in Fourier
// space over the CIE XYZ sensitivities (two orders) and converted to linear Rec. 709. As the
// glTF Sample Viewer: the film's index falls to the outside's 1 as d falls below 0.03 nm
// (smoothstep), the optical path uses the refracted angle (2 η₂ d cos θ₂), and the phase
// shifts are 0 or π. The phase shifts being multiples of π, cos(x + shift) = ±cos x, and the
// second order's cos 2x = 2 cos² x − 1 and e^(−4y) = (e^(−y))⁴: four cosines and four
// exponentials per pixel (lane_math.h), shared by every base F0. ---

// What the film gives every base: the first interface and the sensitivities.
template <class F>
struct ThinFilm {
  F eta;     // the film's index (η₂, or less below 0.03 nm)
  F cos2;    // cos θ₂ inside the film
  F R12;     // Fresnel at the first interface (Schlick), R21 = R12
  F T121;    // 1 − R12
  F x1, y1, z1;  // the first order's sensitivities (XYZ, before the phase shift's sign)
  F x2, y2, z2;  // the second order's (its shift is a multiple of 2π)
};

template <class F>
inline ThinFilm<F> thin_film(F cos1, F film_ior, F thickness) {
  const F one(1.0), zero(0.0);
  ThinFilm<F> tf;
  const F s = simd::clamp(thickness * F(1.0 / 0.03), zero, one);
  tf.eta = one + (film_ior - one) * (s * s * (F(3.0) - s - s));
  const F inv = one / tf.eta;
  const F sin2 = inv * inv * (one - cos1 * cos1);
  tf.cos2 = simd::sqrt(simd::max(one - sin2, zero));
  const F r = (tf.eta - one) / (tf.eta + one);
  const F c = one - cos1, c2 = c * c;
  tf.R12 = r * r + (one - r * r) * (c2 * c2 * c);
  tf.T121 = one - tf.R12;
  // The phase 2π · OPD · 10⁻⁹, OPD = 2 η₂ d cos θ₂ (nm).
  const F phase = F(2.0 * 3.14159265358979323846 * 1e-9) * (F(2.0) * tf.eta * thickness * tf.cos2);
  const F p2 = phase * phase;
  // Each sensitivity: amplitude · cos(position · phase) · e^(−variance · phase²), the
  // amplitudes val √(2π var) / 1.0685·10⁻⁷ of the extension's constants.
  const F cx = cos_lanes(F(1.6810e+06) * phase), cy = cos_lanes(F(1.7953e+06) * phase);
  const F cz = cos_lanes(F(2.2084e+06) * phase), cw = cos_lanes(F(2.2399e+06) * phase);
  const F ex = exp_lanes(F(-4.3278e+09) * p2), ey = exp_lanes(F(-9.3046e+09) * p2);
  const F ez = exp_lanes(F(-6.6121e+09) * p2), ew = exp_lanes(F(-4.5282e+09) * p2);
  const F ax(0.8465900023036574), ay(1.0002218935839293), az(1.0011224857215686), aw(0.15386830651283523);
  tf.x1 = ax * cx * ex + aw * cw * ew;
  tf.y1 = ay * cy * ey;
  tf.z1 = az * cz * ez;
  const auto twice = [](F co) { return co * co * F(2.0) - F(1.0); };
  const auto fourth = [](F e) { return (e * e) * (e * e); };
  tf.x2 = ax * twice(cx) * fourth(ex) + aw * twice(cw) * fourth(ew);
  tf.y2 = ay * twice(cy) * fourth(ey);
  tf.z2 = az * twice(cz) * fourth(ez);
  return tf;
}

// The film's Fresnel reflectance over a base of F0 (each channel in [0, 1]; its index
// (1 + √F0)/(1 − √F0), F0 at most 0.9999), at least 0 (the XYZ → Rec. 709 conversion can
// leave the gamut).
template <class F>
inline simd::Vec3<F> F_iridescence(const ThinFilm<F>& tf, const simd::Vec3<F>& base_f0) {
  const F one(1.0), zero(0.0);
  const F c = one - tf.cos2, c2 = c * c;
  const F c5 = c2 * c2 * c;
  // Per channel: the second interface's R23, the compound terms, and the sign of the first
  // order's phase shift (π + φ23: +1 where the base's index is below the film's, else −1).
  F R23[3], sign[3];
  const F f0[3] = {base_f0.x, base_f0.y, base_f0.z};
  for (int i = 0; i < 3; ++i) {
    const F sf = simd::sqrt(simd::clamp(f0[i], zero, F(0.9999)));
    const F n3 = (one + sf) / (one - sf);
    const F r = (n3 - tf.eta) / (n3 + tf.eta);
    R23[i] = r * r + (one - r * r) * c5;
    sign[i] = simd::select(n3 < tf.eta, one, zero - one);
  }
  // The sensitivities of each order in Rec. 709 (x, y, z take the shift of channel 0, 1, 2,
  // as the extension's evalSensitivity does), times 2.
  const auto rgb = [](F x, F y, F z) {
    return simd::Vec3<F>(F(2.0 * 3.2404542) * x + F(2.0 * -1.5371385) * y + F(2.0 * -0.4985314) * z,
                         F(2.0 * -0.9692660) * x + F(2.0 * 1.8760108) * y + F(2.0 * 0.0415560) * z,
                         F(2.0 * 0.0556434) * x + F(2.0 * -0.2040259) * y + F(2.0 * 1.0572252) * z);
  };
  const simd::Vec3<F> s1 = rgb(tf.x1 * sign[0], tf.y1 * sign[1], tf.z1 * sign[2]);
  const simd::Vec3<F> s2 = rgb(tf.x2, tf.y2, tf.z2);
  const F s1c[3] = {s1.x, s1.y, s1.z}, s2c[3] = {s2.x, s2.y, s2.z};
  F out[3];
  for (int i = 0; i < 3; ++i) {
    const F R123 = simd::clamp(tf.R12 * R23[i], F(1e-5), F(0.9999));
    const F r123 = simd::sqrt(R123);
    const F Rs = tf.T121 * tf.T121 * R23[i] / (one - R123);
    const F C0 = tf.R12 + Rs;
    const F C1 = (Rs - tf.T121) * r123;
    const F C2 = C1 * r123;
    out[i] = simd::max(C0 + C1 * s1c[i] + C2 * s2c[i], zero);
  }
  return {out[0], out[1], out[2]};
}

// F0 of the metal/roughness model: 4% for dielectrics, the base colour for metals.
inline glm::vec3 f0_of(const glm::vec3& base_color, float metallic) {
  return glm::vec3(kDielectricF0) + (base_color - glm::vec3(kDielectricF0)) * metallic;
}
// The same per lane (the same operations as the glm form, per component).
template <class F>
inline simd::Vec3<F> f0_of(const simd::Vec3<F>& base_color, F metallic) {
  return simd::Vec3<F>(F(kDielectricF0)) + (base_color - simd::Vec3<F>(F(kDielectricF0))) * metallic;
}

}  // namespace softpbr::pbr
