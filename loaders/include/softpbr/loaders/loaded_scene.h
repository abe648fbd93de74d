// softpbr/loaders/loaded_scene.h — a scene ready to render as a loader returns it: the
// pbr::Scene with its render settings, animation and estimates. load_scene_file (a JSON
// scene file, scene_file.h) and gltf_scene_file (a glTF model as the command shows it,
// gltf.h) both return one.
#pragma once

#include <cstdint>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "softpbr/pbr/animation.h"
#include "softpbr/pbr/scene.h"
#include "softpbr/pbr/tonemap.h"

namespace softpbr::pbr {

// Render settings: image size, output transform, renderer options.
struct RenderSettings {
  int width = 1280;
  int height = 720;
  OutputSettings output{0.0f, ToneMap::Reinhard, 0.0f};  // exposure, tone map, gamma (0 = sRGB)
  unsigned threads = 0;                                    // 0: all hardware threads
  int tile_size = 64;
  int msaa = 1;  // samples a pixel: 1, 4 or 8 (raster::Target)
};

class GltfPoser;  // gltf.h

struct LoadedScene {
  Scene scene;
  RenderSettings render;
  Animation animation;
  std::uint64_t mesh_bytes = 0;   // memory the scene's meshes and their draws are estimated to need
  std::uint64_t texture_bytes = 0;  // texels of its textures, mip levels included (a shared image counts once)
  std::uint64_t environment_bytes = 0;  // the prefiltered maps of its environment (Environment::bytes())
  std::uint64_t triangles = 0;    // drawn per frame (a shared mesh counts once per object)
  std::vector<std::string> warnings;  // e.g. from OBJ files, one line each, naming the file
  std::vector<std::string> inputs;    // the files read: the scene, models, MTL files, images
  // A glTF model loaded to be posed again (GltfOptions::poseable; the job's fps setting):
  // GltfScene::pose through it, the scene's objects being the model's.
  std::shared_ptr<GltfPoser> poser;
};

// Adds object `o`'s memory to `scene`'s estimate: its draw (raster::draw_geometry_bytes with
// the varyings of the textured shader, the most any material needs) to mesh_bytes, its mesh
// to mesh_bytes and its material's textures to texture_bytes unless `counted` holds them
// (a mesh or image shared by several objects counts once). For scenes made object by
// object (gltf_scene_file, Python's Scene.add); scene files count theirs as they load.
void count_object_memory(LoadedScene& scene, const Object& o, std::set<const void*>& counted);

// The draw part of that estimate, for an object of `vertices` and `triangles`: what a
// loader counts before it builds the objects (glTF instancing: instances × triangles).
std::uint64_t object_draw_bytes(std::uint64_t vertices, std::uint64_t triangles);

// The name scene files (and code written before LoadedScene) give it: the same type.
using SceneFile = LoadedScene;

// The scene at frame `frame` of its animation (frame 0 is the scene as loaded).
inline Scene animate(const LoadedScene& loaded, long frame) {
  return animate(loaded.scene, loaded.animation, frame);
}

}  // namespace softpbr::pbr
