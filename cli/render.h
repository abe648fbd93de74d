// render.h — `softpbr render SCENE -o OUT.png [...]`: a scene file to images, one frame or a
// sharded frame list; `softpbr render a.glb b.glb -o thumbs/{name}.png`: several inputs in
// one run, one renderer for all (see docs/scene-format.md for the scene and the command).
#pragma once

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "softpbr/loaders/gltf.h"

namespace softpbr::cli {

struct RenderArgs {
  std::vector<std::string> scenes;  // one scene file or model, or several (a batch: docs/scene-format.md)
  std::vector<std::string> outputs;
  int width = 0, height = 0, threads = 0, tile_size = 0, msaa = 1;
  std::string tonemap;
  float exposure = 0.0f;
  std::string frames, shard;
  bool force = false;
  bool quiet = false;
  double max_memory_mib = 0;
  std::vector<std::string> roots;  // --root: the folders a scene may read files from
  // A glTF model given instead of a scene file: the view.
  float yaw = 0.0f, pitch = pbr::kDefaultPitch;  // degrees
  int camera = -1;                 // a camera of the file
  // Image-based lighting: a file, "studio" (built in) or "none"; overrides of the scene's.
  std::string env, background, env_cache;
  float env_intensity = 1.0f, env_rotation = 0.0f;
  // Which options were given (command-line values override the scene file's).
  CLI::Option *width_opt = nullptr, *height_opt = nullptr, *threads_opt = nullptr, *tile_opt = nullptr,
              *tonemap_opt = nullptr, *exposure_opt = nullptr, *frames_opt = nullptr, *shard_opt = nullptr,
              *camera_opt = nullptr, *env_opt = nullptr, *env_intensity_opt = nullptr, *env_rotation_opt = nullptr,
              *background_opt = nullptr, *msaa_opt = nullptr;
};

CLI::App* add_render_command(CLI::App& app, RenderArgs& args);
int run_render(const RenderArgs& args);

}  // namespace softpbr::cli
