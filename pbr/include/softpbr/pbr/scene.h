// softpbr/pbr/scene.h — a scene (camera, objects, lights) and rendering it with the PBR shader.
#pragma once

#include <memory>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "softpbr/pbr/camera.h"
#include "softpbr/pbr/light.h"
#include "softpbr/pbr/material.h"
#include "softpbr/pbr/mesh.h"
#include "softpbr/pbr/tonemap.h"
#include "softpbr/raster/renderer.h"
#include "softpbr/raster/target.h"

namespace softpbr::pbr {

struct Object {
  std::shared_ptr<const Mesh> mesh;
  Material material;
  glm::mat4 transform{1.0f};  // model → world
};

struct Scene {
  Camera camera;
  std::vector<Object> objects;
  std::vector<Light> lights;
  glm::vec3 ambient{0.03f, 0.03f, 0.03f};  // ambient light: adds ambient · base colour · ao
  glm::vec4 background{0.0f, 0.0f, 0.0f, 1.0f};  // linear clear colour
};

// Clears the target to the background (depth to 1) and draws every object with
// PbrShader, back faces culled, in one frame of `renderer`. Throws std::invalid_argument
// naming the object or light and field when a value is invalid; nothing is drawn then.
void render(const Scene& scene, raster::Renderer& renderer, raster::Target& target);

// render(), then the output transform into `image` (resized to the target): each tile is
// tone mapped and encoded by the thread that drew it, right after it (ToneMapper). The
// same bytes as tone_map_to_rgba8(target, output) after render(). Throws as both.
void render_rgba8(const Scene& scene, raster::Renderer& renderer, raster::Target& target,
                  const OutputSettings& output, raster::Image8& image);

}  // namespace softpbr::pbr
