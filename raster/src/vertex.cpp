// Per-vertex classification and viewport transform (see vertex.h).
#include "softpbr/raster/vertex.h"

#include "softpbr/raster/clip.h"

namespace softpbr::raster {

void project_vertices(TransformedVertices& v, std::size_t first, std::size_t last, Viewport viewport) {
  for (std::size_t i = first; i < last; ++i) {
    v.outcode[i] = classify(v.position[i], viewport);
    const bool projectable = (v.outcode[i] & (kNeedsClipping | kNotFinite)) == 0;
    v.screen[i] = projectable ? project(v.position[i], viewport) : ScreenVertex{};
  }
}

}  // namespace softpbr::raster
