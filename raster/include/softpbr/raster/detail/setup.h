// softpbr/raster/detail/setup.h — triangle setup in fixed point.
//
// Internal to softpbr::raster (included by renderer.h for its templates): not API, may
// change at any time. The API is renderer.h, shader.h, target.h, color.h, pool.h.
//
// Vertices are snapped to 1/256 pixel. Edge functions are exact 64-bit integers, so a
// pixel on an edge shared by two triangles is covered by exactly one of them (the
// top-left rule, as in D3D10+ and GL: pixel centres at +0.5; a pixel whose centre lies
// exactly on an edge belongs to the triangle for which that edge is a top or left edge).
#pragma once

#include <algorithm>
#include <cstdint>

#include <glm/vec4.hpp>

#include "softpbr/raster/shader.h"

namespace softpbr::raster {

// 8 subpixel bits as in D3D10+ and llvmpipe.
inline constexpr int kSubpixelBits = 8;
inline constexpr std::int64_t kSubpixelScale = std::int64_t{1} << kSubpixelBits;

// Guard band: snapped positions stay within ±kGuardBand pixels of the target's origin.
// Coordinates then fit in 24 bits (2^15 pixels × 2^8), edge coefficients in 25 bits and
// every edge-function value below 2^50, inside int64 with room to spare. Geometry beyond
// it is clipped in clip space (clip.h), so nothing inside the target moves.
inline constexpr int kGuardBand = 32768;

// A set-up triangle. Vertex order is normalised so that the area is positive.
// Edge i (opposite vertex i): E_i(sx, sy) = a[i]·sx + b[i]·sy + c[i], with (sx, sy) a
// sample position in fixed point; E_i ≥ 0 inside. c has the fill-rule bias folded in
// (−1 on edges that are neither top nor left); bias[i] adds it back for the unbiased value
// the barycentric weights use.
struct Triangle {
  std::int32_t a[3];
  std::int32_t b[3];
  std::int64_t c[3];
  std::int32_t bias[3];
  std::int32_t min_x, min_y, max_x, max_y;  // inclusive pixel bounds, inside the target
  float z0, dz1, dz2;                       // window depth: z0 + λ1·dz1 + λ2·dz2
  float inv_area;                           // 1 / (2 × area in fixed-point units²)
  float inv_w[3];                           // 1 / clip w per vertex
  std::uint32_t vertex[3];                  // indices of the vertices' varyings
  bool front_facing;
};

struct Viewport {
  int width;
  int height;
  // Largest offset of a sample from its pixel centre, in 1/256 pixel (0 without MSAA,
  // sample_reach() in target.h): widens the pixel bounds of a triangle to every pixel one of
  // whose samples may lie inside it.
  int sample_reach = 0;
};

// A vertex after the viewport transform.
struct ScreenVertex {
  std::int32_t x, y;  // fixed point, 1/256 pixel, row 0 at the top
  float z;            // window depth: (z/w) · 0.5 + 0.5
  float inv_w;        // 1 / w
};

// The viewport transform of a clip-space position inside the clip volume and guard band
// (computed once per vertex; clipping makes new vertices through the same function).
ScreenVertex project(const glm::vec4& clip, Viewport viewport);

// Sets up the triangle with screen vertices `v` and varyings `ids`. Returns false when it
// covers no sample (zero area, culled, or off the target).
bool setup_triangle(const ScreenVertex v[3], const std::uint32_t ids[3], Viewport viewport,
                    const DrawState& state, Triangle& out);

// setup_triangle() in its three steps, inline for primitive assembly (bin.cpp), which
// culls on the area before it reads anything else of the vertices.

// Twice the signed area of (v0, v1, v2) in fixed-point units²: positive when they run
// clockwise on screen (y down). Exact: coordinates within the guard band fit in 24 bits.
inline std::int64_t screen_area(const ScreenVertex& v0, const ScreenVertex& v1, const ScreenVertex& v2) {
  return (std::int64_t{v1.x} - v0.x) * (std::int64_t{v2.y} - v0.y) -
         (std::int64_t{v1.y} - v0.y) * (std::int64_t{v2.x} - v0.x);
}

// Which orientations a draw keeps: face culling as a pair of flags, decided once a draw.
struct FaceFilter {
  bool clockwise_front;  // a clockwise triangle faces the viewer
  bool keep_clockwise;
  bool keep_counter_clockwise;

  explicit FaceFilter(const DrawState& state) {
    clockwise_front = state.front_face == FrontFace::Clockwise;
    keep_clockwise = !((state.cull == Cull::Back && !clockwise_front) || (state.cull == Cull::Front && clockwise_front));
    keep_counter_clockwise =
        !((state.cull == Cull::Back && clockwise_front) || (state.cull == Cull::Front && !clockwise_front));
  }
  // Whether a triangle of twice the signed area `area` is drawn (zero area never is).
  bool keeps(std::int64_t area) const { return area > 0 ? keep_clockwise : area < 0 && keep_counter_clockwise; }
  // Whether a triangle of non-zero signed area `area` faces the viewer.
  bool front(std::int64_t area) const { return clockwise_front == (area > 0); }
};

// The rest of setup_triangle() for a triangle of non-zero `area` (screen_area()) that
// culling kept; `front` says whether it faces the viewer. Returns false when its bounding
// box holds no sample of the target; `out` is written only when it returns true.
inline bool setup_kept_triangle(const ScreenVertex& v0, const ScreenVertex& v1, const ScreenVertex& v2,
                                std::uint32_t id0, std::uint32_t id1, std::uint32_t id2, std::int64_t area,
                                bool front, Viewport viewport, Triangle& out) {
  // Normalise to positive orientation (clockwise) by swapping vertices 1 and 2.
  const bool clockwise = area > 0;
  const ScreenVertex& p1 = clockwise ? v1 : v2;
  const ScreenVertex& p2 = clockwise ? v2 : v1;
  const std::uint32_t i1 = clockwise ? id1 : id2;
  const std::uint32_t i2 = clockwise ? id2 : id1;

  // Pixels whose centre (i·256 + 128), or one of whose samples (up to sample_reach from
  // it), can lie in the triangle's bounding box. Coordinates are within ±2^23, so int32
  // holds every step; >> floors (arithmetic shift, C++20).
  constexpr std::int32_t scale = kSubpixelScale;
  const std::int32_t up = scale / 2 + viewport.sample_reach;
  const std::int32_t min_fx = std::min(std::min(v0.x, p1.x), p2.x);
  const std::int32_t max_fx = std::max(std::max(v0.x, p1.x), p2.x);
  const std::int32_t min_fy = std::min(std::min(v0.y, p1.y), p2.y);
  const std::int32_t max_fy = std::max(std::max(v0.y, p1.y), p2.y);
  const std::int32_t min_px = std::max(0, (min_fx - up + scale - 1) >> kSubpixelBits);
  const std::int32_t min_py = std::max(0, (min_fy - up + scale - 1) >> kSubpixelBits);
  const std::int32_t down = scale / 2 - viewport.sample_reach;
  const std::int32_t max_px = std::min(viewport.width - 1, (max_fx - down) >> kSubpixelBits);
  const std::int32_t max_py = std::min(viewport.height - 1, (max_fy - down) >> kSubpixelBits);
  if (min_px > max_px || min_py > max_py) return false;

  // Edge i runs from vertex i+1 to vertex i+2: E_i(p) = orient(v[i+1], v[i+2], p)
  //   = (ya − yb)·px + (xb − xa)·py + (yb − ya)·xa − (xb − xa)·ya.
  // Top-left rule (y down, clockwise triangles): a top edge is horizontal and runs to the
  // right (xb > xa); a left edge runs upwards (yb < ya). Other edges exclude their pixels
  // by a bias of −1 (E ≥ 0 becomes E > 0 on integers).
  auto edge = [&out](int i, const ScreenVertex& a, const ScreenVertex& b) {
    const bool top = a.y == b.y && b.x > a.x;
    const bool left = b.y < a.y;
    const std::int32_t bias = (top || left) ? 0 : 1;
    out.a[i] = a.y - b.y;
    out.b[i] = b.x - a.x;
    out.bias[i] = bias;
    out.c[i] = std::int64_t{b.y - a.y} * a.x - std::int64_t{b.x - a.x} * a.y - bias;
  };
  edge(0, p1, p2);
  edge(1, p2, v0);
  edge(2, v0, p1);
  out.min_x = min_px;
  out.min_y = min_py;
  out.max_x = max_px;
  out.max_y = max_py;
  out.z0 = v0.z;
  out.dz1 = p1.z - v0.z;
  out.dz2 = p2.z - v0.z;
  out.inv_area = 1.0f / static_cast<float>(area > 0 ? area : -area);
  out.inv_w[0] = v0.inv_w;
  out.inv_w[1] = p1.inv_w;
  out.inv_w[2] = p2.inv_w;
  out.vertex[0] = id0;
  out.vertex[1] = i1;
  out.vertex[2] = i2;
  out.front_facing = front;
  return true;
}

}  // namespace softpbr::raster
