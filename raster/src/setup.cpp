// Triangle setup in fixed point (see setup.h).
#include "softpbr/raster/detail/setup.h"

#include <algorithm>

namespace softpbr::raster {

namespace {

constexpr std::int64_t kFixedLimit = std::int64_t{kGuardBand} * kSubpixelScale;

// Round to nearest, halves up, for |v| < 2^52 with basic operations only (std::nearbyint
// is a libm call without SSE4.1).
std::int64_t round_fixed(double v) {
  std::int64_t r = static_cast<std::int64_t>(v);  // towards zero
  const double frac = v - static_cast<double>(r);  // exact
  if (frac >= 0.5) ++r;
  else if (frac < -0.5) --r;
  return r;
}

}  // namespace

ScreenVertex project(const glm::vec4& p, Viewport vp) {
  // Clip space → window pixels → fixed point, in double so the snap is exact at any
  // coordinate inside the guard band. y is flipped: row 0 is the top of the image. Clamp
  // first: clipping keeps vertices on the guard band only up to float rounding.
  const double w = p.w;
  const double px = (static_cast<double>(p.x) / w + 1.0) * (0.5 * vp.width);
  const double py = (1.0 - static_cast<double>(p.y) / w) * (0.5 * vp.height);
  const double limit = static_cast<double>(kFixedLimit);
  ScreenVertex v;
  v.x = static_cast<std::int32_t>(round_fixed(std::clamp(px * kSubpixelScale, -limit, limit)));
  v.y = static_cast<std::int32_t>(round_fixed(std::clamp(py * kSubpixelScale, -limit, limit)));
  v.z = (p.z / p.w) * 0.5f + 0.5f;  // NDC [−1, 1] → window [0, 1]
  v.inv_w = 1.0f / p.w;
  return v;
}

bool setup_triangle(const ScreenVertex v[3], const std::uint32_t ids[3], Viewport viewport,
                    const DrawState& state, Triangle& out) {
  const std::int64_t area = screen_area(v[0], v[1], v[2]);
  const FaceFilter faces(state);
  if (!faces.keeps(area)) return false;
  return setup_kept_triangle(v[0], v[1], v[2], ids[0], ids[1], ids[2], area, faces.front(area), viewport, out);
}

}  // namespace softpbr::raster
