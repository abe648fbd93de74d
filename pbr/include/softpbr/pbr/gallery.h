// softpbr/pbr/gallery.h — the paper's scene: a grid of spheres, one row per material,
// roughness rising across the columns, three point lights, the camera in front.
//
// Fixed layout (also the benchmark scene of benchmarks/): unit spacing, centred at the
// origin, sphere radius 0.4; camera at (0, 0, 9) looking at the origin, vertical fov 45°,
// near 0.1, far 100; point lights at (−4, 4, 6), (4, 4, 6), (0, −4, 6), white, intensity
// 60, inverse-square falloff; ambient 0.03. The paper tone maps with Reinhard and gamma
// 2.2 (gallery_output()).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "softpbr/pbr/mesh.h"
#include "softpbr/pbr/scene.h"
#include "softpbr/pbr/tonemap.h"

namespace softpbr::pbr {

struct GalleryOptions {
  // Material preset per row, top to bottom (see material_presets()).
  std::vector<std::string> rows{"gold", "copper", "aluminium", "titanium", "plastic_red"};
  int columns = 7;
  float first_roughness = 0.05f;  // left column
  float last_roughness = 1.0f;    // right column
  int segments = 64;              // UV sphere segments around; rings = segments / 2
  // Draw this mesh (scaled to fit a 0.8-unit cube, centred) in place of the spheres,
  // turned by mesh_yaw radians about the y axis (the default turns a model that faces −z,
  // as spot does, to show its face and left side).
  std::shared_ptr<const Mesh> mesh;
  float mesh_yaw = 2.5f;
};

// Throws std::invalid_argument for an unknown preset name or a grid with no cell.
Scene make_gallery(const GalleryOptions& options = {});

// The paper's output transform: Reinhard, then gamma 2.2.
inline OutputSettings gallery_output() { return {0.0f, ToneMap::Reinhard, 2.2f}; }

}  // namespace softpbr::pbr
