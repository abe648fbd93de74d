// How the command shows a glTF model (see gltf.h, GltfView).
#include <set>
#include <stdexcept>
#include <string>

#include "softpbr/dmath/dmath.h"
#include "softpbr/loaders/gltf.h"
#include "softpbr/pbr/environment.h"

namespace softpbr::pbr {

LoadedScene gltf_scene_file(GltfScene g, const GltfView& view, const std::string& name) {
  LoadedScene f;
  f.warnings = std::move(g.warnings);
  f.scene.objects = std::move(g.objects);
  f.triangles = g.triangles;
  f.render.width = view.width;
  f.render.height = view.height;
  if (view.camera >= 0) {
    if (static_cast<std::size_t>(view.camera) >= g.cameras.size())
      throw std::invalid_argument("camera: " + name + " has " + std::to_string(g.cameras.size()) + " cameras, no camera " +
                                  std::to_string(view.camera));
    f.scene.camera = g.cameras[static_cast<std::size_t>(view.camera)].camera;
  } else {
    if (!(view.pitch >= -89.0f && view.pitch <= 89.0f) || !std::isfinite(view.yaw))
      throw std::invalid_argument("pitch: expected degrees in [-89, 89]; yaw: a finite number of degrees");
    f.scene.camera = framing_camera(world_bounds(f.scene.objects),
                                    static_cast<float>(view.width) / static_cast<float>(view.height),
                                    static_cast<float>(dmath::radians(view.yaw)),
                                    static_cast<float>(dmath::radians(view.pitch)));
  }
  f.scene.ambient = glm::vec3(kDefaultAmbient);
  f.scene.background = {0.05f, 0.05f, 0.06f, 1.0f};
  if (view.environment) {
    f.scene.environment.map = Environment::studio(view.pool);
    f.scene.background_mode = BackgroundMode::Blur;
    f.scene.lights = std::move(g.lights);
    f.environment_bytes = f.scene.environment.map->bytes();
  } else {
    f.scene.lights = g.lights.empty() ? default_light_rig(f.scene.camera) : std::move(g.lights);
  }
  // Memory: the meshes and their draws, and textures.
  std::set<const void*> counted;
  for (const Object& o : f.scene.objects) count_object_memory(f, o, counted);
  return f;
}

}  // namespace softpbr::pbr
