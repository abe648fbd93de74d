// ground.h — internal to softpbr::pbr: the shadow catcher under a scene's objects
// (Scene::ground; docs/design.md, "Ground").
//
// render() fits the ground to the objects' bounds (ground_setup), draws the casters' depth
// seen from below into a depth-only target with the projection it gives (the shadow maps'
// depth-only path) and, when the environment has a dominant light (dominant_light), a
// shadow map along it; turns those depths and the lights' shadow maps into the ground's
// opacity (ground_texture), and draws ground_object() — a black, unlit, blended square with
// that opacity as its alpha — before the other blended objects.
#pragma once

#include <memory>
#include <span>
#include <vector>

#include <glm/mat4x4.hpp>

#include "softpbr/pbr/environment_lookup.h"
#include "softpbr/pbr/light.h"
#include "softpbr/pbr/mesh.h"
#include "softpbr/pbr/scene.h"
#include "softpbr/raster/pool.h"
#include "softpbr/raster/texture.h"

namespace softpbr::pbr::detail {

// Texels a side of the depth seen from below and of the ground's texture.
inline constexpr int kGroundSize = 512;

// Where the ground lies: the square [x0, x0 + side] × [z0, z0 + side] on the plane y (the
// bottom of the objects' bounds), and how its shadow is made.
struct GroundSetup {
  float y = 0.0f;
  float x0 = 0.0f, z0 = 0.0f, side = 0.0f;
  // Heights above the ground over which the contact shadow fades to nothing: the depth seen
  // from below is 0 at the ground and 1 at y + reach.
  float reach = 0.0f;
  // Box radii in texels of the blur of what touches the ground and of what is at `reach`
  // (three passes of each: the blur spreads 3 radii).
  int blur_near = 1, blur_far = 1;
  // World → clip space of the view from below: clip x along +x, clip y along −z (row 0 of
  // the target at z0), window depth (y' − y) / reach.
  glm::mat4 view_projection{1.0f};
};

// Where a light that casts shadows on the ground is: a direction towards it (directional
// lights, the environment's dominant light) or a position (point and spot lights).
struct GroundLight {
  bool directional = true;
  glm::vec3 to_light{0.0f, 1.0f, 0.0f};  // unit, directional
  glm::vec3 position{0.0f};               // point and spot
};

// Fits the ground under `world` (the objects' bounds): its square holds their footprint,
// the shadows that `lights` throw of the bounds' corners on the plane (each at most two
// widths from the footprint's centre: a grazing light's shadow is cut there), and the far
// blur's spread around them. False when there is nothing to put it under (empty or
// degenerate bounds, no width on the ground).
bool ground_setup(const Bounds& world, const Ground& ground, const std::vector<GroundLight>& lights, GroundSetup& out);

// The environment's dominant light, if it has one above the horizon: the direction
// (world, towards it) of the brightest texel of its irradiance map, and its strength
// (E_max − E_min) / (E_max + E_min) of the map's luminances — near 1 for a sun over a dark
// ground, 0 for a uniform sky.
struct DominantLight {
  glm::vec3 to_light{0.0f, 1.0f, 0.0f};
  float strength = 0.0f;
};
bool dominant_light(const PreparedEnvironment& environment, DominantLight& out);

// The ground's opacity as an RGBA8 texture (black, the opacity as alpha): the contact
// shadow from `depths` (kGroundSize² window depths of the casters seen from below, 1 where
// none is), each height blurred by its distance to the ground, over it the share of the
// lights' light that their shadow maps (PreparedLight::shadow) say is blocked at the ground,
// and with `sky` (a map drawn along the environment's dominant light, `dominant`) the
// dominant light's strength where it is blocked, softened by the near blur.
// Rows in parallel on `pool`: the same bits for any thread count.
std::shared_ptr<const raster::Texture> ground_texture(const GroundSetup& setup, const Ground& ground,
                                                      std::span<const float> depths,
                                                      const std::vector<PreparedLight>& lights, const ShadowMap* sky,
                                                      const DominantLight& dominant, raster::ThreadPool& pool);

// The ground as an object: the square facing up, unlit black with `texture`'s alpha,
// blended; it casts and receives no shadows.
Object ground_object(const GroundSetup& setup, std::shared_ptr<const raster::Texture> texture);

// Bytes a frame holds for the ground: its depth target, its texture and buffers, and the
// map of an environment's dominant light (a shadow map's 16 MiB).
std::uint64_t ground_bytes();

}  // namespace softpbr::pbr::detail
