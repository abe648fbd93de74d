// softpbr/raster/setup.h — triangle setup in fixed point.
//
// Vertices are snapped to 1/256 pixel. Edge functions are exact 64-bit integers, so a
// pixel on an edge shared by two triangles is covered by exactly one of them (the
// top-left rule, as in D3D10+ and GL: pixel centres at +0.5; a pixel whose centre lies
// exactly on an edge belongs to the triangle for which that edge is a top or left edge).
#pragma once

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
// covers no pixel centre (zero area, culled, or off the target).
bool setup_triangle(const ScreenVertex v[3], const std::uint32_t ids[3], Viewport viewport,
                    const DrawState& state, Triangle& out);

}  // namespace softpbr::raster
