// tone_map_operators.h — the tone-mapping operators of tonemap.h, written once against a
// lane type F (private to pbr/src): float for one pixel (apply_tone_map, the scalar
// encoder), simd::Vec<N> for N pixels (the lanes kernels of ToneMapper::encode). Every lane
// computes the same IEEE operations in the same order as float does (simd.h), so all
// paths give the same bits.
//
// Comparisons are written as simd::min/max/clamp, whose choice rules are those of glm and
// std (min(a, b) = b < a ? b : a, max(a, b) = a < b ? b : a, clamp = min(max(x, lo), hi),
// std::min({r, g, b}) = min(min(r, g), b)), which decide where NaN and −0 go; branches are
// selects of both sides (PBR Neutral's compression is computed for every lane and kept
// where peak ≥ 0.76; a discarded lane's quotient may be Inf or NaN, which no lane keeps).
#pragma once

#include "softpbr/pbr/tonemap.h"
#include "softpbr/simd/simd.h"

namespace softpbr::pbr::tone_map_operators {

// Narkowicz 2015, "ACES Filmic Tone Mapping Curve": x(ax + b) / (x(cx + d) + e), clamped
// to [0, 1]; per channel.
template <class F>
inline F aces_fit(F x) {
  constexpr float a = 2.51f, b = 0.03f, c = 2.43f, d = 0.59f, e = 0.14f;  // the fit's coefficients
  return simd::clamp((x * (F(a) * x + F(b))) / (x * (F(c) * x + F(d)) + F(e)), F(0.0f), F(1.0f));
}

// Khronos PBR Neutral tone mapper (Khronos 3D Commerce, 2024), as its reference GLSL: an
// offset for the darkest channel, then above the compression start a hyperbolic roll-off of
// the peak channel and a desaturation towards it. Not clamped.
template <class F>
inline void pbr_neutral(F& r, F& g, F& b) {
  constexpr float kStartCompression = 0.8f - 0.04f;
  constexpr float kDesaturation = 0.15f;
  constexpr float d = 1.0f - kStartCompression;
  const F x = simd::min(simd::min(r, g), b);
  const F offset = simd::select(x < F(0.08f), x - F(6.25f) * x * x, F(0.04f));
  r -= offset;
  g -= offset;
  b -= offset;
  const F peak = simd::max(simd::max(r, g), b);
  const F new_peak = F(1.0f) - F(d * d) / (peak + F(d) - F(kStartCompression));
  const F ratio = new_peak / peak;
  const F mix = F(1.0f) - F(1.0f) / (F(kDesaturation) * (peak - new_peak) + F(1.0f));
  const F keep = F(1.0f) - mix, toward = new_peak * mix;
  const auto compress = [&](F c) { return (c * ratio) * keep + toward; };
  const auto below = peak < F(kStartCompression);
  r = simd::select(below, r, compress(r));
  g = simd::select(below, g, compress(g));
  b = simd::select(below, b, compress(b));
}

// The operator kOp on linear colour (after exposure), in place.
template <ToneMap kOp, class F>
inline void tone_map(F& r, F& g, F& b) {
  // From 1e9 on every operator already returns its maximum (1), so the upper clamp changes
  // no finite result; it keeps +Inf (Inf / Inf) and the ACES fit's x² overflow above ~1e19
  // from turning into NaN, which would encode as black. NaN stays NaN (encoded as 0).
  const auto limit = [](F c) { return simd::min(simd::max(c, F(0.0f)), F(1e9f)); };
  r = limit(r);
  g = limit(g);
  b = limit(b);
  if constexpr (kOp == ToneMap::None) {
    r = simd::min(r, F(1.0f));
    g = simd::min(g, F(1.0f));
    b = simd::min(b, F(1.0f));
  } else if constexpr (kOp == ToneMap::Reinhard) {  // Reinhard et al. 2002, c / (1 + c)
    r = r / (F(1.0f) + r);
    g = g / (F(1.0f) + g);
    b = b / (F(1.0f) + b);
  } else if constexpr (kOp == ToneMap::Aces) {
    r = aces_fit(r);
    g = aces_fit(g);
    b = aces_fit(b);
  } else {
    pbr_neutral(r, g, b);
    r = simd::clamp(r, F(0.0f), F(1.0f));
    g = simd::clamp(g, F(0.0f), F(1.0f));
    b = simd::clamp(b, F(0.0f), F(1.0f));
  }
}

}  // namespace softpbr::pbr::tone_map_operators
