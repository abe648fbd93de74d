// softpbr/raster/detail/clip.h — culling and clipping in homogeneous clip space.
//
// Internal to softpbr::raster (included by renderer.h for its templates): not API, may
// change at any time. The API is renderer.h, shader.h, target.h, color.h, pool.h.
//
// Triangles entirely outside one frustum plane are culled. The rest are clipped only
// against the planes that matter for correctness: near (z ≥ −w, GL convention), far
// (z ≤ w), w ≥ kMinClipW (so a triangle partly behind the camera is clipped, never
// mirrored), and — only when a vertex leaves it — the guard band of setup.h, so fixed
// point never overflows. Everything else is left to the scissor of the rasterizer.
//
// Intersections are always computed from the inside vertex towards the outside one, so an
// edge shared by two triangles is cut at the same point in both: clipping stays watertight.
#pragma once

#include <cstdint>

#include <glm/vec4.hpp>

#include "softpbr/raster/detail/setup.h"
#include "softpbr/raster/shader.h"

namespace softpbr::raster {

// Smallest clip w kept: positions with w below it are behind or at the eye.
inline constexpr float kMinClipW = 1e-5f;

// Most vertices a clipped triangle can have: 3 + one per clipping plane (7).
inline constexpr int kMaxClipVertices = 10;

struct ClipVertex {
  glm::vec4 position;
  float varyings[kMaxVaryings];
};

// Outcode bits of a clip-space vertex: one per side of the view volume it lies beyond,
// and two summaries.
enum : std::uint16_t {
  kRightOfFrustum = 0x01,   // x > w
  kLeftOfFrustum = 0x02,    // x < −w
  kBelowFrustum = 0x04,     // y > w
  kAboveFrustum = 0x08,     // y < −w
  kBeyondFar = 0x10,        // z > w
  kBeforeNear = 0x20,       // z < −w
  kBehindEye = 0x40,        // w < kMinClipW
  kOutsideFrustum = 0x7f,   // any of the above
  kNeedsClipping = 0x80,    // outside near, far, w ≥ kMinClipW or the guard band
  kNotFinite = 0x100,       // a NaN or Inf coordinate
};
static_assert((kRightOfFrustum | kLeftOfFrustum | kBelowFrustum | kAboveFrustum | kBeyondFar | kBeforeNear |
               kBehindEye) == kOutsideFrustum);

// The outcode of one vertex for a target of this size; 0 means the vertex is inside the
// view volume and a triangle of such vertices needs no clipping.
std::uint16_t classify(const glm::vec4& position, Viewport viewport);

enum class ClipResult : std::uint8_t {
  Culled,    // nothing left
  Inside,    // no clipping needed: use the triangle as it is
  Clipped    // a convex polygon of ≥ 3 vertices in the output
};

// Classifies a triangle; rejects non-finite positions. When clipping is needed, writes
// the clipped polygon (positions and `varying_count` varyings) to `out` and its size to
// `count`.
ClipResult clip_triangle(const glm::vec4 position[3], const float* const varyings[3], int varying_count,
                         Viewport viewport, ClipVertex out[kMaxClipVertices], int& count);

}  // namespace softpbr::raster
