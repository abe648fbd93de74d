// Procedural meshes.
#include "softpbr/pbr/mesh.h"

#include <stdexcept>

#include "softpbr/raster/dmath.h"

namespace softpbr::pbr {

Mesh uv_sphere(float radius, int segments, int rings) {
  if (!(radius > 0.0f) || segments < 3 || rings < 2)
    throw std::invalid_argument("uv_sphere: need radius > 0, segments >= 3, rings >= 2");
  namespace dm = dmath;
  Mesh mesh;
  mesh.vertices.reserve(static_cast<std::size_t>(segments + 1) * (rings + 1));
  for (int r = 0; r <= rings; ++r) {
    const double v = static_cast<double>(r) / rings;
    const double theta = v * dm::kPi;  // from the north pole (+y)
    const double st = dm::sin(theta), ct = dm::cos(theta);
    for (int s = 0; s <= segments; ++s) {
      const double u = static_cast<double>(s) / segments;
      const double phi = u * 2.0 * dm::kPi;
      const glm::vec3 n(static_cast<float>(st * dm::sin(phi)), static_cast<float>(ct),
                        static_cast<float>(st * dm::cos(phi)));
      mesh.vertices.push_back({n * radius, n, {static_cast<float>(u), static_cast<float>(v)}});
    }
  }
  const auto row = static_cast<std::uint32_t>(segments + 1);
  for (int r = 0; r < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      const std::uint32_t i0 = static_cast<std::uint32_t>(r) * row + static_cast<std::uint32_t>(s);
      const std::uint32_t i1 = i0 + 1, i2 = i0 + row, i3 = i2 + 1;
      // Counter-clockwise seen from outside; the degenerate pole triangles are skipped.
      if (r != 0) mesh.indices.insert(mesh.indices.end(), {i0, i2, i1});
      if (r != rings - 1) mesh.indices.insert(mesh.indices.end(), {i1, i2, i3});
    }
  return mesh;
}

}  // namespace softpbr::pbr
