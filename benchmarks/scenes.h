// benchmarks/scenes.h — the fixed benchmark scenes of issue 6, shared by bench_scenes
// (Google Benchmark) and compare_llvmpipe (the same scenes on Mesa's llvmpipe).
//
//   gallery        the paper's gallery: 7×3 spheres of radius 0.4, spacing 1, centred at
//                  the origin; rows gold, copper, red dielectric (0.8, 0.1, 0.1);
//                  roughness 0.05 → 1 across the columns; uv spheres of S segments × S
//                  rings (64: 169,344 triangles); camera at (0, 0, 9) looking at the
//                  origin, fovy 45°, near 0.1, far 100; point lights at (−4, 4, 6),
//                  (4, 4, 6), (0, −4, 6), intensity 60, inverse square; ambient 0.03 ×
//                  base colour; Reinhard, then gamma 1/2.2. Back faces culled.
//   fill           fill rate: 8 camera-facing planes that each cover the whole view,
//                  drawn back to front so the depth test passes every time: every pixel
//                  is shaded 8 times by the same PBR equation (16 triangles).
//   mesh_<name>    the gallery with a real mesh from ../shared/models in every cell.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "softpbr/pbr/scene.h"
#include "softpbr/pbr/tonemap.h"

namespace softpbr::bench {

struct BenchScene {
  std::string name;       // e.g. "gallery64_1080p"
  int width = 1920;
  int height = 1080;
  pbr::Scene scene;
  pbr::OutputSettings output;
  int overdraw = 1;       // how many times each covered pixel is shaded
  std::size_t triangles = 0;  // submitted per frame
};

// The gallery with `segments` × `segments` uv spheres at width × height.
BenchScene gallery_scene(int segments, int width, int height);

// Fill rate at width × height: `layers` full-view planes, back to front.
BenchScene fill_scene(int width, int height, int layers = 8);

// The gallery with each cell showing `obj` (fitted into a 0.8 cube). Throws as load_obj.
BenchScene mesh_scene(const std::string& name, const std::filesystem::path& obj, int width, int height);

// Every scene of issue 6: gallery 64 at 1080p, 16 and 256 segments at 1080p, 64 at
// 512×512, fill at 1080p, and the shared meshes when `shared_models` exists (skipped
// cleanly, with a note on stderr, otherwise).
std::vector<BenchScene> all_scenes(const std::filesystem::path& shared_models);

// Where ../shared/models is for a program run from the build tree: $SOFTPBR_SHARED_MODELS
// if set, else the source tree's ../shared/models.
std::filesystem::path default_shared_models();

}  // namespace softpbr::bench
