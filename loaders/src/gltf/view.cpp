// How a glTF model is shown (see gltf.h): the bounds of its objects, the camera that frames
// them, the light rig without lights, and GltfView's scene (gltf_scene_file).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <map>
#include <set>
#include <stdexcept>
#include <string>

#include "softpbr/dmath/dmath.h"
#include "softpbr/loaders/gltf.h"
#include "softpbr/loaders/load_error.h"
#include "softpbr/pbr/environment.h"

namespace softpbr::pbr {

namespace {

// `degrees` (finite) reduced modulo 360 into (−180, 180], exactly: an angle of 1e25° is
// the angle it is modulo 360 (sin and cos of its radians would be of a rounded value, far
// outside the range dmath's reduction is exact in). Angles already in (−180, 180] are
// returned unchanged, so they frame as before. No fmod: below 2^52 the quotient's floor
// leaves an exact remainder (x − 360q is a multiple of x's last place below 720, which
// fits 53 bits, and 360q < 2^52 is exact); from 2^52 on x is an integer m · 2^k, and its
// remainder is (m mod 360) · (2^k mod 360) mod 360 in integers.
double reduce_degrees(double x) {
  if (x > -180.0 && x <= 180.0) return x;
  double r = 0.0;
  if (std::fabs(x) < 4503599627370496.0) {  // 2^52
    const double q = std::floor(x / 360.0);
    r = x - 360.0 * q;
    if (r < 0.0) r += 360.0;
    if (r >= 360.0) r -= 360.0;
  } else {
    int e = 0;
    const double m = std::ldexp(std::frexp(std::fabs(x), &e), 53);  // |x| = m · 2^(e − 53), m an integer
    std::uint64_t power = 1;                                          // 2^(e − 53) mod 360
    for (int k = 53; k < e; ++k) power = power * 2 % 360;
    const std::uint64_t rest = static_cast<std::uint64_t>(m) % 360 * power % 360;
    r = static_cast<double>(x < 0.0 ? (360 - rest) % 360 : rest);
  }
  return r > 180.0 ? r - 360.0 : r;
}

bool finite3(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

std::string show(const glm::vec3& v) {
  char text[96];
  std::snprintf(text, sizeof text, "(%g, %g, %g)", static_cast<double>(v.x), static_cast<double>(v.y),
                static_cast<double>(v.z));
  return text;
}

}  // namespace

LoadedScene gltf_scene_file(GltfScene g, const GltfView& view, const std::string& name) {
  LoadedScene f;
  f.warnings = std::move(g.warnings);
  f.scene.objects = std::move(g.objects);
  f.triangles = g.triangles;
  f.poser = g.poser;
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
    // A model whose bounds float cannot hold, or which is too large or too small for a
    // camera in float to frame (positions near 3.4e38, a node scaling by 1e38, a model
    // 1e-40 across), is an input error naming the file, not an invalid camera later.
    const Bounds b = view.bounds ? *view.bounds : world_bounds(f.scene.objects);
    if (!b.empty() && (!finite3(b.min) || !finite3(b.max)))
      throw LoadError(name + ": the automatic camera cannot frame the model: its bounds " + show(b.min) + " to " +
                      show(b.max) + " reach beyond float's range (a vertex or a node's transform near 3.4e38)");
    f.scene.camera = framing_camera(b, static_cast<float>(view.width) / static_cast<float>(view.height),
                                    static_cast<float>(dmath::radians(reduce_degrees(view.yaw))),
                                    static_cast<float>(dmath::radians(view.pitch)));
    try {
      validate(f.scene.camera);
    } catch (const std::invalid_argument& e) {
      throw LoadError(name + ": the automatic camera cannot frame the model's bounds " + show(b.min) + " to " +
                      show(b.max) + " in float precision (" + e.what() + ")" +
                      (g.cameras.empty() ? std::string() : "; its own cameras can (--camera)"));
    }
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
  std::map<const Mesh*, Bounds> of_mesh;  // each mesh's bounds once, however many its instances
  for (const Object& o : objects) {
    if (!o.mesh) continue;
    auto [it, added] = of_mesh.try_emplace(o.mesh.get());
    if (added) it->second = bounds(*o.mesh);
    const Bounds b = it->second;
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
  glm::dvec3 centre(b.centre());
  glm::dvec3 extent(b.extent());
  // Bounds near float's range overflow the float sums: then in double.
  if (!std::isfinite(centre.x + centre.y + centre.z + extent.x + extent.y + extent.z)) {
    centre = (glm::dvec3(b.min) + glm::dvec3(b.max)) * 0.5;
    extent = glm::dvec3(b.max) - glm::dvec3(b.min);
  }
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
