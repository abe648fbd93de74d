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
//
// Textured (issue 13): the same scenes with benchmark_texture() as every material's base
// colour texture (sRGB, trilinear, repeat), drawn by pbr's TexturedPbrShader:
//   fill8x_tex     the fill planes with their UVs scaled by 8: ~2.8–3.9 texels per pixel
//                  (λ 1.5–2, levels 1–3 read), isotropic
//   fill8x_aniso16 the same planes with u scaled 7.5× more than v (30 × 4): 8 probes along
//                  u (max_anisotropy 16), λ 0.4–0.9
//   gallery64_tex  the 64-segment gallery, the texture on every sphere (uv_sphere's UVs)
//
// Image-based lighting (issue 15):
//   gallery_ibl    examples/scenes/gallery_ibl.json as the scene file has it (5 × 7 uv
//                  spheres of 64 segments × 32 rings: gold, copper, aluminium, titanium,
//                  red plastic, roughness 0.05 → 1; no lights; lit by the built-in studio
//                  Environment::studio() alone, the environment as the background; ACES,
//                  sRGB), at the benchmark's size instead of the file's 1280×720. The
//                  studio is prefiltered once, when the scene is loaded (not per frame).
#pragma once

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <glm/vec2.hpp>

#include "softpbr/pbr/scene.h"
#include "softpbr/pbr/tonemap.h"
#include "softpbr/raster/texture.h"

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

// The textured scenes' base colour: a 2048² sRGB RGBA8 texture with its mip chain (12
// levels), built once: 32 × 32 cells of 64 texels, each a colour from an integer hash of
// the cell, darker on alternate cells (a checker), with per-texel hash noise of ±24 codes
// and a 2-texel light line along the cells' top and left edges. Integer arithmetic only:
// the same bytes everywhere.
std::shared_ptr<const raster::Texture> benchmark_texture();

// fill_scene() with benchmark_texture() on every plane, the planes' UVs multiplied by
// `uv_scale`, a sampler with `max_anisotropy`; named "fill<layers>x_<tag>_<size>".
BenchScene textured_fill_scene(int width, int height, const std::string& tag, glm::vec2 uv_scale,
                               int max_anisotropy, int layers = 8);

// gallery_scene() with benchmark_texture() on every sphere (trilinear, isotropic).
BenchScene textured_gallery_scene(int segments, int width, int height);

// examples/scenes/gallery_shadows.json at width × height — the gallery before a wall, one
// directional light that casts shadows — and the same with its shadows off:
// gallery_shadows_<size>, gallery_noshadows_<size> (their ratio is the shadows' cost).
std::vector<BenchScene> shadow_gallery_scenes(int width, int height);

// examples/scenes/gallery_ibl.json at width × height (see above). Throws SceneFileError.
BenchScene ibl_gallery_scene(int width, int height);

// Variants of ibl_gallery_scene() that split its frame time (bench_scenes only):
//   gallery_ibl_onelevel   every roughness rounded to the nearest prefiltered level (i / 5):
//                          one level lookup a sphere pixel instead of two
//   gallery_ibl_nobg       the background a colour: no background pass
//   gallery_ibl_noocclusion  without the screen-space occlusion (its cost; compare_llvmpipe's
//                          gallery_ibl is this one: the GLSL has no occlusion)
//   gallery_ibl_ambient    no environment, the constant ambient (PbrShader without lights)
//                          and a colour background: the raster work and tone map alone
//   gallery_ibl_bgonly     the background pass alone (no objects)
//   gallery_ibl_empty      nothing but the clear and the tone map of the cleared tiles
std::vector<BenchScene> ibl_gallery_variants(int width, int height);
// The IBL gallery with each layer of the material extensions on every material, and all of
// them: gallery_layers_{specular,clearcoat,sheen,all,anisotropy,iridescence,transmission}_<size>.
std::vector<BenchScene> layered_gallery_variants(int width, int height);

// Variants of fill_scene(width, height) that split its frame time (bench_scenes only),
// named "fill8x_<tag>_<size>":
//   lights0, lights1, lights2  the first 0, 1 or 2 of the 3 lights (lights0: the ambient
//                              and emission alone), so frame time against light count
//                              gives one light's cost and a packet's cost without lights
//   layers1 (named fill1x_*)   one plane: the per-frame part (clear, tone map, encode)
//                              plus one layer
std::vector<BenchScene> fill_variants(int width, int height);

// The gallery with each cell showing `obj` (fitted into a 0.8 cube). Throws as load_obj.
BenchScene mesh_scene(const std::string& name, const std::filesystem::path& obj, int width, int height);

// Every scene of issue 6: gallery 64 at 1080p, 16 and 256 segments at 1080p, 64 at
// 512×512, fill at 1080p; issue 13's textured fill (trilinear and 16× anisotropic) and
// textured 64-segment gallery at 1080p; issue 15's IBL gallery at 1080p; and the shared meshes when `shared_models` exists
// (skipped cleanly, with a note on stderr, otherwise).
std::vector<BenchScene> all_scenes(const std::filesystem::path& shared_models);

// Where ../shared/models is for a program run from the build tree: $SOFTPBR_SHARED_MODELS
// if set, else the source tree's ../shared/models.
std::filesystem::path default_shared_models();

}  // namespace softpbr::bench
