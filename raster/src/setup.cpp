// Triangle setup in fixed point (see setup.h).
#include "softpbr/raster/setup.h"

#include <algorithm>
#include <utility>

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

// Twice the signed area of (a, b, c): positive when a → b → c runs clockwise on screen.
std::int64_t orient(std::int64_t ax, std::int64_t ay, std::int64_t bx, std::int64_t by, std::int64_t cx,
                    std::int64_t cy) {
  return (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
}

// Floor division by 256 for possibly negative fixed-point values.
std::int64_t floor_pixel(std::int64_t v) { return v >> kSubpixelBits; }

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
  const std::int64_t x[3] = {v[0].x, v[1].x, v[2].x};
  const std::int64_t y[3] = {v[0].y, v[1].y, v[2].y};
  const std::int64_t area = orient(x[0], y[0], x[1], y[1], x[2], y[2]);
  if (area == 0) return false;

  // On screen (y down) a positive orientation is clockwise.
  const bool clockwise = area > 0;
  const bool front = (state.front_face == FrontFace::Clockwise) == clockwise;
  if ((state.cull == Cull::Back && !front) || (state.cull == Cull::Front && front)) return false;

  // Normalise to positive orientation by swapping vertices 1 and 2.
  int order[3] = {0, 1, 2};
  if (!clockwise) std::swap(order[1], order[2]);
  std::int64_t vx[3], vy[3];
  for (int i = 0; i < 3; ++i) {
    vx[i] = x[order[i]];
    vy[i] = y[order[i]];
  }

  // Pixels whose centre (i·256 + 128) can lie in the triangle's bounding box.
  const std::int64_t min_fx = std::min({vx[0], vx[1], vx[2]});
  const std::int64_t max_fx = std::max({vx[0], vx[1], vx[2]});
  const std::int64_t min_fy = std::min({vy[0], vy[1], vy[2]});
  const std::int64_t max_fy = std::max({vy[0], vy[1], vy[2]});
  const std::int64_t half = kSubpixelScale / 2;
  const std::int64_t min_px = std::max<std::int64_t>(0, floor_pixel(min_fx - half + kSubpixelScale - 1));
  const std::int64_t min_py = std::max<std::int64_t>(0, floor_pixel(min_fy - half + kSubpixelScale - 1));
  const std::int64_t max_px = std::min<std::int64_t>(viewport.width - 1, floor_pixel(max_fx - half));
  const std::int64_t max_py = std::min<std::int64_t>(viewport.height - 1, floor_pixel(max_fy - half));
  if (min_px > max_px || min_py > max_py) return false;

  // Edge i runs from vertex i+1 to vertex i+2: E_i(p) = orient(v[i+1], v[i+2], p)
  //   = (ya − yb)·px + (xb − xa)·py + (yb − ya)·xa − (xb − xa)·ya.
  // Top-left rule (y down, clockwise triangles): a top edge is horizontal and runs to the
  // right (xb > xa); a left edge runs upwards (yb < ya). Other edges exclude their pixels
  // by a bias of −1 (E ≥ 0 becomes E > 0 on integers).
  for (int i = 0; i < 3; ++i) {
    const int ia = (i + 1) % 3, ib = (i + 2) % 3;
    const std::int64_t xa = vx[ia], ya = vy[ia], xb = vx[ib], yb = vy[ib];
    const bool top = ya == yb && xb > xa;
    const bool left = yb < ya;
    out.a[i] = static_cast<std::int32_t>(ya - yb);
    out.b[i] = static_cast<std::int32_t>(xb - xa);
    out.bias[i] = (top || left) ? 0 : 1;
    out.c[i] = (yb - ya) * xa - (xb - xa) * ya - out.bias[i];
  }
  out.min_x = static_cast<std::int32_t>(min_px);
  out.min_y = static_cast<std::int32_t>(min_py);
  out.max_x = static_cast<std::int32_t>(max_px);
  out.max_y = static_cast<std::int32_t>(max_py);

  float z[3];
  for (int i = 0; i < 3; ++i) {
    z[i] = v[order[i]].z;
    out.inv_w[i] = v[order[i]].inv_w;
    out.vertex[i] = ids[order[i]];
  }
  out.z0 = z[0];
  out.dz1 = z[1] - z[0];
  out.dz2 = z[2] - z[0];
  out.inv_area = 1.0f / static_cast<float>(area > 0 ? area : -area);
  out.front_facing = front;
  return true;
}

}  // namespace softpbr::raster
