// How a glTF model is shown (see gltf.h): the bounds of its objects, the camera that frames
// them, the light rig without lights, and GltfView's scene (gltf_scene_file).
#include <algorithm>
#include <cmath>
#include <limits>
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

Bounds world_bounds(const std::vector<Object>& objects) {
  Bounds all{glm::vec3(std::numeric_limits<float>::infinity()), glm::vec3(-std::numeric_limits<float>::infinity())};
  for (const Object& o : objects) {
    if (!o.mesh) continue;
    const Bounds b = bounds(*o.mesh);
    if (b.empty()) continue;
    for (int k = 0; k < 8; ++k) {
      const glm::vec3 corner((k & 1) ? b.max.x : b.min.x, (k & 2) ? b.max.y : b.min.y, (k & 4) ? b.max.z : b.min.z);
      const glm::vec3 w(o.transform * glm::vec4(corner, 1.0f));
      all = merge(all, Bounds{w, w});
    }
  }
  return all;
}

Camera framing_camera(const Bounds& b, float aspect, float yaw, float pitch) {
  Camera c;
  if (b.empty()) return c;
  const double fovy = dmath::radians(45.0);
  const double half_v = fovy / 2.0;
  // The horizontal half-angle: atan(tan(φ/2) · aspect).
  const double half_h = dmath::atan2(dmath::tan(half_v) * aspect, 1.0);
  const double half = std::min(half_v, half_h);
  const glm::dvec3 centre(b.centre());
  const glm::dvec3 extent(b.extent());
  double r = std::sqrt(glm::dot(extent, extent)) / 2.0;
  if (!(r > 0.0)) r = 1.0;
  const double d = r / dmath::sin(half) * 1.05;
  const glm::dvec3 dir(dmath::sin(yaw) * dmath::cos(pitch), dmath::sin(pitch), dmath::cos(yaw) * dmath::cos(pitch));
  c.position = glm::vec3(centre + dir * d);
  c.target = glm::vec3(centre);
  // Straight up or down: "up" is the direction the camera would have faced at pitch 0.
  const double cp = dmath::cos(pitch);
  c.up = cp > 1e-6 ? glm::vec3(0.0f, 1.0f, 0.0f)
                   : glm::vec3(glm::dvec3(-dmath::sin(yaw), 0.0, -dmath::cos(yaw)) * (pitch > 0 ? 1.0 : -1.0));
  c.fovy = static_cast<float>(fovy);
  c.near = static_cast<float>(std::max(d - 1.5 * r, d / 1000.0));
  c.far = static_cast<float>(d + 1.5 * r);
  return c;
}

std::vector<Light> default_light_rig(const Camera& camera) {
  // A frame of the view: forward f (camera → target), right x, up y.
  glm::vec3 f = camera.target - camera.position;
  f = glm::normalize(f);
  glm::vec3 x = glm::cross(f, camera.up);
  x = glm::length(x) > 0.0f ? glm::normalize(x) : glm::vec3(1.0f, 0.0f, 0.0f);
  const glm::vec3 y = glm::cross(x, f);
  auto directional = [&](glm::vec3 travel, float intensity) {
    Light l;
    l.type = LightType::Directional;
    l.direction = glm::normalize(travel);
    l.intensity = intensity;
    return l;
  };
  // Directions the light travels, in the view frame.
  return {directional(x * 0.6f - y * 0.8f + f * 0.6f, 2.5f),   // key: from the upper left, in front
          directional(-x * 1.0f - y * 0.2f + f * 0.5f, 0.8f),  // fill: from the right
          directional(-y * 0.5f - f * 1.0f, 1.5f)};            // rim: from behind, above
}

}  // namespace softpbr::pbr
