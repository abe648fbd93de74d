// Culling and clipping in homogeneous clip space (see clip.h).
#include "softpbr/raster/detail/clip.h"

#include <cmath>
#include <cstring>

namespace softpbr::raster {

namespace {

// A clip plane: inside where a·x + b·y + c·z + d·w + e ≥ 0, evaluated in this order.
// Distances and cut points are computed in double and rounded once to float. In float, a
// ±1e6 edge cut at the guard band landed a pixel or more off its line on screen, an edge
// from w = 4e5 to w = −0.1 cut at w = kMinClipW could land at w ≤ 0 (a mirrored vertex),
// and coordinates near ±3e38 overflowed to NaN vertices.
struct Plane {
  float a, b, c, d, e;
  double distance(const glm::vec4& p) const {
    return double{a} * p.x + double{b} * p.y + double{c} * p.z + double{d} * p.w + double{e};
  }
};

bool finite(const glm::vec4& p) {
  return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z) && std::isfinite(p.w);
}

// From a towards b by t in [0, 1], in double, rounded once to float.
float lerp(float a, float b, double t) { return static_cast<float>(a + t * (static_cast<double>(b) - a)); }

// Sutherland–Hodgman against one plane. The intersection on an edge is computed from its
// inside end towards its outside end, whichever way the polygon runs along it.
int clip_polygon(const Plane& plane, const ClipVertex* in, int n, ClipVertex* out, int varying_count) {
  int m = 0;
  for (int i = 0; i < n; ++i) {
    const ClipVertex& p = in[i];
    const ClipVertex& q = in[(i + 1) % n];
    const double dp = plane.distance(p.position);
    const double dq = plane.distance(q.position);
    const bool p_in = dp >= 0.0;
    const bool q_in = dq >= 0.0;
    if (p_in) out[m++] = p;
    if (p_in != q_in) {
      const ClipVertex& inside = p_in ? p : q;
      const ClipVertex& outside = p_in ? q : p;
      const double di = p_in ? dp : dq;
      const double dout = p_in ? dq : dp;
      const double t = di / (di - dout);  // in [0, 1]: di ≥ 0 > dout
      ClipVertex& r = out[m++];
      for (int c = 0; c < 4; ++c) r.position[c] = lerp(inside.position[c], outside.position[c], t);
      for (int k = 0; k < varying_count; ++k) r.varyings[k] = lerp(inside.varyings[k], outside.varyings[k], t);
    }
  }
  return m;
}

struct ClipPlanes {
  Plane planes[7];
};

ClipPlanes clip_planes(Viewport viewport) {
  // Guard band in NDC: pixel x = (ndc + 1) · W/2 must stay in [−G, G]; pixel y = (1 − ndc) · H/2 too.
  const float gx_max = 2.0f * kGuardBand / viewport.width - 1.0f;
  const float gx_min = -2.0f * kGuardBand / viewport.width - 1.0f;
  const float gy_max = 1.0f + 2.0f * kGuardBand / viewport.height;
  const float gy_min = 1.0f - 2.0f * kGuardBand / viewport.height;
  return {{
      {0, 0, 1, 1, 0},             // near: z ≥ −w
      {0, 0, -1, 1, 0},            // far: z ≤ w
      {0, 0, 0, 1, -kMinClipW},    // w ≥ kMinClipW: never mirror what is behind the eye
      {-1, 0, 0, gx_max, 0},       // guard band, right
      {1, 0, 0, -gx_min, 0},       // guard band, left
      {0, 1, 0, -gy_min, 0},       // guard band, top (y up in NDC)
      {0, -1, 0, gy_max, 0},       // guard band, bottom
  }};
}

}  // namespace

std::uint16_t classify(const glm::vec4& p, Viewport viewport) {
  if (!finite(p)) return kNotFinite;
  std::uint16_t code = 0;
  if (p.x > p.w) code |= kRightOfFrustum;
  if (p.x < -p.w) code |= kLeftOfFrustum;
  if (p.y > p.w) code |= kBelowFrustum;
  if (p.y < -p.w) code |= kAboveFrustum;
  if (p.z > p.w) code |= kBeyondFar;
  if (p.z < -p.w) code |= kBeforeNear;
  if (p.w < kMinClipW) code |= kBehindEye;
  // Inside the frustum means inside the guard band too: only test the planes otherwise.
  if (code != 0) {
    const ClipPlanes cp = clip_planes(viewport);
    for (const Plane& plane : cp.planes)
      if (!(plane.distance(p) >= 0.0f)) code |= kNeedsClipping;
  }
  return code;
}

ClipResult clip_triangle(const glm::vec4 position[3], const float* const varyings[3], int varying_count,
                         Viewport viewport, ClipVertex out[kMaxClipVertices], int& count) {
  count = 0;
  if (!finite(position[0]) || !finite(position[1]) || !finite(position[2])) return ClipResult::Culled;

  const ClipPlanes cp = clip_planes(viewport);
  const Plane* planes = cp.planes;

  // Frustum culling: all three vertices outside one of the six view planes.
  auto all_outside = [&](auto&& outside) {
    return outside(position[0]) && outside(position[1]) && outside(position[2]);
  };
  if (all_outside([](const glm::vec4& p) { return p.x > p.w; }) ||
      all_outside([](const glm::vec4& p) { return p.x < -p.w; }) ||
      all_outside([](const glm::vec4& p) { return p.y > p.w; }) ||
      all_outside([](const glm::vec4& p) { return p.y < -p.w; }) ||
      all_outside([](const glm::vec4& p) { return p.z > p.w; }) ||
      all_outside([](const glm::vec4& p) { return p.z < -p.w; }) ||
      all_outside([](const glm::vec4& p) { return p.w < kMinClipW; }))
    return ClipResult::Culled;

  unsigned needed = 0;
  for (int i = 0; i < 7; ++i)
    for (int v = 0; v < 3; ++v)
      if (!(planes[i].distance(position[v]) >= 0.0f)) needed |= 1u << i;
  if (needed == 0) return ClipResult::Inside;

  ClipVertex buffers[2][kMaxClipVertices];
  int n = 3;
  for (int v = 0; v < 3; ++v) {
    buffers[0][v].position = position[v];
    if (varying_count > 0) std::memcpy(buffers[0][v].varyings, varyings[v], sizeof(float) * varying_count);
  }
  int current = 0;
  for (int i = 0; i < 7 && n >= 3; ++i) {
    if (!(needed & (1u << i))) continue;
    n = clip_polygon(planes[i], buffers[current], n, buffers[1 - current], varying_count);
    current = 1 - current;
  }
  if (n < 3) return ClipResult::Culled;
  // With coordinates beyond ~1e15 the cut at w = kMinClipW is below double's resolution
  // and can leave w ≤ 0, which project() would divide by: drop the triangle rather than
  // draw it mirrored.
  for (int v = 0; v < n; ++v)
    if (!(buffers[current][v].position.w > 0.0f)) return ClipResult::Culled;
  for (int v = 0; v < n; ++v) out[v] = buffers[current][v];
  count = n;
  return ClipResult::Clipped;
}

}  // namespace softpbr::raster
