// softpbr/pbr/light.h — punctual lights: point, directional and spot.
//
// Falloff follows glTF's KHR_lights_punctual: point and spot lights fall off with the
// inverse square of distance, optionally windowed to zero at `range`; spot lights fade
// smoothly between the inner and outer cone.
#pragma once

#include <algorithm>
#include <cmath>
#include <memory>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "softpbr/simd/simd.h"

namespace softpbr::pbr {

enum class LightType { Point, Directional, Spot };

struct Light {
  LightType type = LightType::Point;
  glm::vec3 position{0.0f, 0.0f, 0.0f};    // point and spot
  glm::vec3 direction{0.0f, -1.0f, 0.0f};  // directional and spot: where the light travels
  glm::vec3 color{1.0f, 1.0f, 1.0f};       // linear
  float intensity = 1.0f;                  // radiance scale: point/spot at 1 m, or directional
  float range = 0.0f;                      // point/spot: 0 = unlimited, else zero at this distance
  float inner_cone = 0.0f;                 // spot: full intensity inside this angle (radians)
  float outer_cone = 0.7853981633974483f;  // spot: zero outside this angle (radians), π/4 default
  // Whether the light casts shadows (a shadow map, shadow.h): objects with cast_shadows
  // block it for objects with receive_shadows. Off by default here and in scene files; glTF
  // lights (KHR_lights_punctual) turn it on.
  bool shadows = false;
};

struct ShadowMap;  // shadow.h

// Direction towards the light and the incident radiance Li at a surface point.
struct LightSample {
  glm::vec3 to_light;  // unit
  glm::vec3 radiance;  // Li, zero outside the light's reach
};

// Per-light values that need no per-pixel work: the unit direction and the spot cone
// scale/offset (cosines computed once with dmath).
struct PreparedLight {
  Light light;
  glm::vec3 unit_direction;
  float cone_scale;
  float cone_offset;
  glm::vec3 radiance{0.0f};  // color · intensity, once (not per packet)
  // The light's shadow map for this frame (render() sets it for a light with shadows), or
  // null: the light shines through everything, and the shaders run no shadow code for it.
  const ShadowMap* shadow = nullptr;
};

// Validates and prepares a light. Throws std::invalid_argument naming the field when a
// value is not finite, negative, or a zero direction.
PreparedLight prepare_light(const Light& light);

// Li at `position` (KHR_lights_punctual falloff), written once against a lane type F
// (float or simd::Vec<N>). For a point at the light's position the squared distance is
// clamped to 1e-8 so the result stays finite.
template <class F>
struct LightSampleLanes {
  simd::Vec3<F> to_light;  // unit
  // The radiance arriving is PreparedLight::radiance (colour × intensity, uniform) times
  // this: distance, range window and cone; 1 for a directional light. The shader folds it
  // into n·l. (The uniform part is not copied in here: GCC moved such a member through
  // the stack in 8-byte pieces every light.)
  F falloff;
};

// One result object, written in place on every path: with a return expression per light
// type GCC built each in a temporary and copied it out in 16-byte halves, and the 32-byte
// loads of those halves missed store forwarding (about 17% of the fill
// kernel's time on Zen 3).
template <class F>
inline LightSampleLanes<F> sample_light(const PreparedLight& p, const simd::Vec3<F>& position) {
  using V3 = simd::Vec3<F>;
  const Light& l = p.light;
  LightSampleLanes<F> out;
  if (l.type == LightType::Directional) {
    out.to_light = V3(F(-p.unit_direction.x), F(-p.unit_direction.y), F(-p.unit_direction.z));
    out.falloff = F(1.0f);
    return out;
  }
  const V3 d = V3(F(l.position.x), F(l.position.y), F(l.position.z)) - position;
  const F dist2 = simd::max(simd::dot(d, d), F(1e-8f));
  const F dist = simd::sqrt(dist2);
  const F inv_dist = F(1.0f) / dist;
  out.to_light = d * inv_dist;
  F falloff = inv_dist * inv_dist;
  if (l.range > 0.0f) {
    // KHR_lights_punctual's window: clamp(1 − (d/range)⁴, 0, 1) / d².
    const F q = dist2 / F(l.range * l.range);
    falloff *= simd::clamp(F(1.0f) - q * q, F(0.0f), F(1.0f));
  }
  if (l.type == LightType::Spot) {
    const V3 u(F(p.unit_direction.x), F(p.unit_direction.y), F(p.unit_direction.z));
    const F cd = simd::dot(u, -out.to_light);
    const F a = simd::clamp(cd * F(p.cone_scale) + F(p.cone_offset), F(0.0f), F(1.0f));
    falloff *= a * a;
  }
  out.falloff = falloff;
  return out;
}

// The same for one point, with glm vectors.
inline LightSample sample_light(const PreparedLight& p, const glm::vec3& position) {
  const LightSampleLanes<float> s = sample_light(p, simd::Vec3<float>(position.x, position.y, position.z));
  return {{s.to_light.x, s.to_light.y, s.to_light.z}, p.radiance * s.falloff};
}

class Environment;  // environment.h

// Image-based lighting, a scene's light from every direction: an environment map
// (environment.h) with its rotation and intensity. The shaders read it prepared
// (prepare_environment, environment_lookup.h).
struct EnvironmentLighting {
  std::shared_ptr<const Environment> map;
  float intensity = 1.0f;
  float rotation = 0.0f;      // degrees about +Y
  bool multiscatter = true;   // Fdez-Agüera 2019 energy compensation
  // Screen-space ambient occlusion of this light on opaque and masked objects (docs/design.md,
  // "Image-based lighting"): a depth and normal pass and a per-pixel factor, the light of
  // crevices and contacts dimmed. Off: the image is the one without it, bit for bit.
  bool occlusion = true;
};

}  // namespace softpbr::pbr
