// softpbr/pbr/light.h — punctual lights: point, directional and spot.
//
// Falloff follows glTF's KHR_lights_punctual: point and spot lights fall off with the
// inverse square of distance, optionally windowed to zero at `range`; spot lights fade
// smoothly between the inner and outer cone.
#pragma once

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

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
};

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
};

// Validates and prepares a light. Throws std::invalid_argument naming the field when a
// value is not finite, negative, or a zero direction.
PreparedLight prepare_light(const Light& light);

// Li at `position` (KHR_lights_punctual falloff). For a point at the light's position the
// squared distance is clamped to 1e-8 so the result stays finite.
inline LightSample sample_light(const PreparedLight& p, const glm::vec3& position) {
  const Light& l = p.light;
  const glm::vec3 scaled = l.color * l.intensity;
  if (l.type == LightType::Directional) return {-p.unit_direction, scaled};

  const glm::vec3 d = l.position - position;
  const float dist2 = std::max(glm::dot(d, d), 1e-8f);
  const float dist = std::sqrt(dist2);
  const glm::vec3 to_light = d / dist;
  float falloff = 1.0f / dist2;
  if (l.range > 0.0f) {
    // KHR_lights_punctual's window: clamp(1 − (d/range)⁴, 0, 1) / d².
    const float q = dist2 / (l.range * l.range);
    falloff *= std::clamp(1.0f - q * q, 0.0f, 1.0f);
  }
  if (l.type == LightType::Spot) {
    const float cd = glm::dot(p.unit_direction, -to_light);
    const float a = std::clamp(cd * p.cone_scale + p.cone_offset, 0.0f, 1.0f);
    falloff *= a * a;
  }
  return {to_light, scaled * falloff};
}

}  // namespace softpbr::pbr
