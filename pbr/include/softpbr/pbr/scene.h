// softpbr/pbr/scene.h — a scene (camera, objects, lights) and rendering it with the PBR shader.
#pragma once

#include <cstdint>
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
  // Shadows (docs/design.md, "Shadows"): whether the object blocks the lights that cast
  // shadows (Light::shadows), and whether it is darkened where they are blocked.
  bool cast_shadows = true;
  bool receive_shadows = true;
};

// What is seen where no object is: the colour `background` (alpha 0 for a transparent
// image), the environment itself, or the environment blurred (its prefiltered radiance at
// roughness background_blur).
enum class BackgroundMode : std::uint8_t { Color, Environment, Blur };

// A ground under the objects (docs/design.md, "Ground"). With `shadow`, a shadow catcher: a
// square on the plane under the objects' bounds, drawn after the opaque objects, black with
// the shadow as its alpha — so that over a transparent background the image's alpha is the
// shadow, which composites onto any page. The shadow is the objects' soft contact shadow
// (their depth seen from below, what is higher above the ground fainter and more blurred)
// and, over it, the shadows that the lights casting shadows (Light::shadows) and the
// environment's dominant light throw on it.
struct Ground {
  bool shadow = false;
  float darkness = 0.7f;  // the shadow's opacity where an object touches the ground, [0, 1]
  float softness = 0.5f;  // [0, 1]: how far the shadow of what is high above the ground spreads
};

struct Scene {
  Camera camera;
  std::vector<Object> objects;
  std::vector<Light> lights;
  // Ambient light: adds ambient · base colour · ao — when there is no environment.
  glm::vec3 ambient{0.03f, 0.03f, 0.03f};
  glm::vec4 background{0.0f, 0.0f, 0.0f, 1.0f};  // linear clear colour
  // Image-based lighting (environment.h): with a map, every object is lit by it besides
  // the lights, and the ambient term is not added.
  EnvironmentLighting environment;
  BackgroundMode background_mode = BackgroundMode::Color;
  float background_blur = 0.3f;  // roughness of BackgroundMode::Blur, [0, 1]
  Ground ground;
};

// Bytes a frame of width × height pixels holds besides its target when the scene has a
// transmissive object: the opaque pass's resolved copy (16 bytes a pixel) and its float
// texture with the mip chain. (A transient multisampled target's sample planes, which such
// a frame allocates, are what a kept target holds: image_memory counts them.)
std::uint64_t transmission_memory(int width, int height);

// Bytes a frame of width × height pixels holds besides its target when the scene's
// environment has occlusion on: the 1-sample depth and normal target and two floats a pixel.
std::uint64_t occlusion_memory(int width, int height);

// Bytes a frame of the scene holds besides its target for its shadow maps: a depth-only
// target a face for each light with shadows (16 MiB a directional or spot light, 24 MiB a
// point light's six faces), and for its ground's shadow (20 MiB).
std::uint64_t shadow_memory(const Scene& scene);

// Clears the target to the background (depth to 1), draws the environment as the
// background when background_mode asks for it, then every object with PbrShader (or
// TexturedPbrShader), back faces culled, in one frame of `renderer`: the opaque and masked
// objects, the background, then — when there are any — the transmissive objects (farthest
// first) over a mip-mapped copy of what those left (Renderer::flush), then the blended ones
// (farthest first). Throws
// std::invalid_argument naming the object, light or field when a value is invalid
// (a background mode other than Color without an environment included); nothing is drawn then.
void render(const Scene& scene, raster::Renderer& renderer, raster::Target& target);

// render(), then the output transform into `image` (resized to the target): each tile is
// tone mapped and encoded by the thread that drew it, right after it (ToneMapper). The
// same bytes as tone_map_to_rgba8(target, output) after render(). Throws as both.
void render_rgba8(const Scene& scene, raster::Renderer& renderer, raster::Target& target,
                  const OutputSettings& output, raster::Image8& image);

// render(), and for each tile, by the thread that drew it while its samples are in cache:
// the output transform into `image` when it is not null (as render_rgba8), and the linear
// colour into `linear` when it is not null — a 1-sample target of the target's size, given
// raster::resolve_box's values (a copy at one sample; depth: sample 0's), so that .hdr and
// .exr output of it is that of the target. With a transient multisampled target
// (raster::SampleStorage::Transient) this is how a frame is kept: `linear` takes a fifth
// of a 4× target's memory (a ninth at 8×). Throws as render(), and std::invalid_argument
// when `linear` is not 1-sample or not the target's size.
void render_outputs(const Scene& scene, raster::Renderer& renderer, raster::Target& target,
                    const OutputSettings& output, raster::Image8* image, raster::Target* linear);

}  // namespace softpbr::pbr
