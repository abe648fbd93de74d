// Per-vertex classification and viewport transform (see vertex.h).
#include "softpbr/raster/detail/vertex.h"

#include "softpbr/raster/detail/clip.h"
#include "softpbr/simd/dispatch.h"

// detail::{baseline, avx2, avx512}::classify_project_lanes().
#define SOFTPBR_TARGET_FILE "vertex-inl.h"
#include "softpbr/simd/foreach_target.h"

namespace softpbr::raster {

namespace detail {
namespace {
auto classify_project_for(simd::Isa isa) { return SOFTPBR_DISPATCH(isa, classify_project_lanes); }
}  // namespace
}  // namespace detail

void project_vertices(TransformedVertices& v, std::size_t first, std::size_t last, Viewport viewport) {
  project_vertices(v, first, last, viewport, simd::cpu_isa());
}

void project_vertices(TransformedVertices& v, std::size_t first, std::size_t last, Viewport viewport,
                      simd::Isa isa) {
  if (first >= last) return;
  const glm::vec4* p = v.position.data() + first;
  std::uint16_t* outcode = v.outcode.data() + first;
  ScreenVertex* screen = v.screen.data() + first;
  const std::size_t n = last - first;
  const std::uint16_t any = detail::classify_project_for(isa)(p, n, viewport, outcode, screen);
  if ((any & kOutsideFrustum) == 0) return;  // the common case: every vertex in view
  // Vertices outside the frustum: classify() adds the guard-band and clip-plane tests, and
  // a vertex that needs clipping is not projected.
  for (std::size_t i = 0; i < n; ++i) {
    if ((outcode[i] & kOutsideFrustum) == 0) continue;
    outcode[i] = classify(p[i], viewport);
    if ((outcode[i] & kNeedsClipping) != 0) screen[i] = ScreenVertex{};
  }
}

}  // namespace softpbr::raster
