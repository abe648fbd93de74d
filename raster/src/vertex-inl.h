// The vertex stage's classification and viewport transform, four vertices at a time,
// compiled once per target (vertex.cpp includes it through softpbr/simd/foreach_target.h;
// no include guard, no header included here).

namespace softpbr::raster::detail::SOFTPBR_TARGET_NS {

// Four lanes as plain vectors (simd::native_t); a comparison gives a lane mask of all ones
// or zeros.
using F4 = simd::native_t<float, 4>;
using I4 = simd::native_t<std::int32_t, 4>;
using D4 = simd::native_t<double, 4>;
using L4 = simd::native_t<std::int64_t, 4>;
using simd::SOFTPBR_TARGET_NS::bit_select;

// round_fixed() of project() on four lanes, clamp included. Each value goes through the
// very IEEE operations project() applies to it (the build has -ffp-contract=off):
//  - the clamp is std::clamp's for every number; a NaN (only from a vertex that is not
//    projected) clamps to a bound instead of passing through, so the conversion to int is
//    always defined;
//  - the clamped value fits in int32 (|v| ≤ 2^23), so converting to int32 truncates as
//    round_fixed()'s conversion to int64 does, and its two rounding tests cannot both
//    hold, so applying both is its if/else.
inline I4 snap(D4 v) {
  const double limit = static_cast<double>(std::int64_t{kGuardBand} * kSubpixelScale);
  const L4 above = v > -limit, below = v < limit;  // both on the unclamped value
  v = bit_select(above, v, D4{} - limit);
  v = bit_select(below, v, D4{} + limit);
  const I4 r = __builtin_convertvector(v, I4);  // towards zero
  const D4 frac = v - __builtin_convertvector(r, D4);  // exact
  // A true lane mask is −1: subtracting it adds one.
  return r - __builtin_convertvector(frac >= 0.5, I4) + __builtin_convertvector(frac < -0.5, I4);
}

// project() and the trivial half of classify() for four vertices, without branches.
// Outcodes are exact for vertices inside the frustum (0) and non-finite ones; the rest
// (x/y/z/w bits set) are left for classify() to add the guard-band test, which
// project_vertices() does afterwards. A non-finite vertex gets a zero screen vertex.
// Returns the OR of the four outcodes.
inline std::uint16_t classify_project4(const glm::vec4* p, Viewport vp, std::uint16_t* outcode, ScreenVertex* screen) {
  const F4 x = {p[0].x, p[1].x, p[2].x, p[3].x};
  const F4 y = {p[0].y, p[1].y, p[2].y, p[3].y};
  const F4 z = {p[0].z, p[1].z, p[2].z, p[3].z};
  const F4 w = {p[0].w, p[1].w, p[2].w, p[3].w};
  // std::isfinite on the bits: exponent not all ones.
  const I4 exponent = I4{} + 0x7f800000;
  const I4 finite = (((I4)x & exponent) != exponent) & (((I4)y & exponent) != exponent) &
                    (((I4)z & exponent) != exponent) & (((I4)w & exponent) != exponent);
  const F4 minus_w = -w;
  const I4 bits = ((x > w) & int{kRightOfFrustum}) | ((x < minus_w) & int{kLeftOfFrustum}) |
                  ((y > w) & int{kBelowFrustum}) | ((y < minus_w) & int{kAboveFrustum}) |
                  ((z > w) & int{kBeyondFar}) | ((z < minus_w) & int{kBeforeNear}) |
                  ((w < kMinClipW) & int{kBehindEye});
  const I4 code = (bits & finite) | ((I4{} + int{kNotFinite}) & ~finite);

  const D4 dw = __builtin_convertvector(w, D4);
  const D4 px = (__builtin_convertvector(x, D4) / dw + 1.0) * (0.5 * vp.width);
  const D4 py = (1.0 - __builtin_convertvector(y, D4) / dw) * (0.5 * vp.height);
  const I4 sx = snap(px * static_cast<double>(kSubpixelScale)) & finite;
  const I4 sy = snap(py * static_cast<double>(kSubpixelScale)) & finite;
  const F4 sz = bit_select(finite, (z / w) * 0.5f + 0.5f, F4{});
  const F4 inv_w = bit_select(finite, 1.0f / w, F4{});
  for (int k = 0; k < 4; ++k) {
    outcode[k] = static_cast<std::uint16_t>(code[k]);
    screen[k] = ScreenVertex{sx[k], sy[k], sz[k], inv_w[k]};
  }
  return static_cast<std::uint16_t>(code[0] | code[1] | code[2] | code[3]);
}

// All n vertices, four at a time; the last few through a padded copy.
SOFTPBR_KERNEL std::uint16_t classify_project_lanes(const glm::vec4* p, std::size_t n, Viewport vp, std::uint16_t* outcode,
                                            ScreenVertex* screen) {
  std::uint16_t any = 0;
  std::size_t i = 0;
  for (; i + 4 <= n; i += 4) any |= classify_project4(p + i, vp, outcode + i, screen + i);
  if (i < n) {
    glm::vec4 pad[4] = {glm::vec4(0, 0, 0, 1), glm::vec4(0, 0, 0, 1), glm::vec4(0, 0, 0, 1), glm::vec4(0, 0, 0, 1)};
    std::uint16_t pad_code[4];
    ScreenVertex pad_screen[4];
    for (std::size_t k = i; k < n; ++k) pad[k - i] = p[k];
    classify_project4(pad, vp, pad_code, pad_screen);
    for (std::size_t k = i; k < n; ++k) {
      outcode[k] = pad_code[k - i];
      screen[k] = pad_screen[k - i];
      any |= pad_code[k - i];
    }
  }
  return any;
}

}  // namespace softpbr::raster::detail::SOFTPBR_TARGET_NS
