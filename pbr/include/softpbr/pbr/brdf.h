// softpbr/pbr/brdf.h — the terms of the Cook-Torrance microfacet BRDF, one small function each.
//
// Names follow Filament ("Physically Based Rendering in Filament", R. Guy & M. Agopian):
// D_ = normal distribution, G_ = geometric shadowing-masking, F_ = Fresnel, Fd_ = diffuse.
// NoH = n·h, NoV = n·v, NoL = n·l, VoH = v·h, all clamped to [0, 1] by the caller.
// α = roughness² (perceptual roughness squared, Burley 2012).
//
// The specular lobe is f_s = D · G · F / (4 · NoL · NoV); G_Smith returns G, not the
// visibility term V = G / (4 · NoL · NoV).
#pragma once

#include <glm/vec3.hpp>

namespace softpbr::pbr {

inline constexpr float kPi = 3.14159265358979323846f;
inline constexpr float kInvPi = 0.318309886183790671538f;
// The same constants in double for the templates: T(kPiDouble) is exact for double and
// rounds to the very same float as kPi for float (likewise kInvPiDouble and kInvPi).
inline constexpr double kPiDouble = 3.14159265358979323846;
inline constexpr double kInvPiDouble = 0.318309886183790671538;
static_assert(static_cast<float>(kPiDouble) == kPi && static_cast<float>(kInvPiDouble) == kInvPi);

// Trowbridge & Reitz 1975 / Walter et al. 2007 ("GGX"): D(h) = α² / (π ((n·h)²(α² − 1) + 1)²).
// Normalised: ∫ D(h) (n·h) dω_h = 1 over the hemisphere.
template <class T>
inline T D_GGX(T NoH, T alpha) {
  const T a2 = alpha * alpha;
  // ≥ a2 > 0 for NoH in [0, 1]. Precision: in float, a2 − 1 rounds to a multiple of 2⁻²⁴,
  // so at kMinRoughness (a2 ≈ 4·10⁻⁶) the peak 1/(π α²) comes out 0.6% low and ∫ D (n·h) dω
  // 0.25% low; 2·10⁻⁴ low at roughness 0.1, less above (tests/test_brdf.cpp).
  const T d = NoH * NoH * (a2 - T(1)) + T(1);
  return a2 / (T(kPiDouble) * d * d);
}

// Schlick 1994 with Karis 2013's k for direct light, k = (roughness + 1)² / 8:
// G1(x) = x / (x (1 − k) + k). Returns G1, not a visibility term.
template <class T>
inline T G_SchlickGGX(T NoX, T k) {
  return NoX / (NoX * (T(1) - k) + k);
}

// k of G_SchlickGGX for analytic (direct) lights, from perceptual roughness (Karis 2013,
// "Real Shading in Unreal Engine 4").
template <class T>
inline T k_direct(T roughness) {
  const T r1 = roughness + T(1);
  return r1 * r1 / T(8);
}

// Smith 1967, separable form: G(l, v) = G1(n·v) · G1(n·l). Returns G.
template <class T>
inline T G_Smith(T NoV, T NoL, T k) {
  return G_SchlickGGX(NoV, k) * G_SchlickGGX(NoL, k);
}

// Schlick 1994: F = F0 + (1 − F0)(1 − v·h)^5; the fifth power as multiplies, exact and
// deterministic (no pow).
inline glm::vec3 F_Schlick(const glm::vec3& f0, float VoH) {
  const float m = 1.0f - VoH;
  const float m2 = m * m;
  const float m5 = m2 * m2 * m;
  return f0 + (glm::vec3(1.0f) - f0) * m5;
}

// Lambert: a perfectly diffuse surface reflects c/π in every direction. Returns the BRDF
// without the albedo: multiply by c.
template <class T>
inline T Fd_Lambert() {
  return T(kInvPiDouble);
}

// F0 of the metal/roughness model: 4% for dielectrics, the base colour for metals.
inline glm::vec3 f0_of(const glm::vec3& base_color, float metallic) {
  return glm::vec3(0.04f) + (base_color - glm::vec3(0.04f)) * metallic;
}

}  // namespace softpbr::pbr
