// softpbr/pbr/shading.h — the reflectance equation over all lights, and the PBR shader.
//
//   Lo = Σ_lights (kD · c/π + D · G · F / (4 (n·l)(n·v))) · Li · (n·l)
//        + ambient · c · ao + emissive,          kD = (1 − F)(1 − metallic)
//
// with D_GGX, G_Smith (Schlick-GGX, k = (r+1)²/8) and F_Schlick from brdf.h. Nothing here
// produces NaN or Inf for finite inputs: roughness is raised to kMinRoughness, n·v is
// clamped to kMinNoV (interpolated normals may face away from the viewer), lights with
// n·l ≤ 0 are skipped, and zero-length normals fall back to the view direction.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <span>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "softpbr/pbr/brdf.h"
#include "softpbr/pbr/light.h"
#include "softpbr/pbr/material.h"
#include "softpbr/pbr/mesh.h"
#include "softpbr/raster/shader.h"

namespace softpbr::pbr {

// Smallest n·v used by the specular term: keeps G1(n·v)/(n·v) ≤ 1/k finite at grazing
// angles and for normals facing away.
inline constexpr float kMinNoV = 1e-4f;

// A material ready for shading: roughness clamped to [kMinRoughness, 1], everything else
// checked to be finite and in range.
struct ShadingMaterial {
  glm::vec3 albedo;     // base colour
  glm::vec3 f0;         // mix(0.04, base colour, metallic)
  float metallic;
  float roughness;      // perceptual, clamped
  float alpha;          // roughness²
  float k;              // (roughness + 1)² / 8
  float ao;
  glm::vec3 emissive;
};

// Throws std::invalid_argument naming the field for NaN/Inf or out-of-range values
// (metallic, roughness and ao must be in [0, 1]; colours non-negative).
ShadingMaterial prepare_material(const Material& m);

// v / |v|, or `fallback` when v has zero length (or is not finite).
inline glm::vec3 normalize_or(const glm::vec3& v, const glm::vec3& fallback) {
  const float len2 = glm::dot(v, v);
  if (!(len2 > 0.0f) || !(len2 < std::numeric_limits<float>::infinity())) return fallback;
  return v / std::sqrt(len2);
}

// The BRDF f(l, v) = kD · c/π + D · G · F / (4 (n·l)(n·v)) for unit n, l, v with n·l > 0.
inline glm::vec3 brdf(const ShadingMaterial& m, const glm::vec3& n, const glm::vec3& l, const glm::vec3& v) {
  const glm::vec3 h = normalize_or(l + v, n);
  const float NoL = std::clamp(glm::dot(n, l), 0.0f, 1.0f);
  const float NoV = std::clamp(glm::dot(n, v), kMinNoV, 1.0f);
  const float NoH = std::clamp(glm::dot(n, h), 0.0f, 1.0f);
  const float VoH = std::clamp(glm::dot(v, h), 0.0f, 1.0f);
  const float D = D_GGX(NoH, m.alpha);
  const float G = G_Smith(NoV, NoL, m.k);
  const glm::vec3 F = F_Schlick(m.f0, VoH);
  const glm::vec3 specular = F * (D * G / (4.0f * NoV * std::max(NoL, kMinNoV)));
  const glm::vec3 kD = (glm::vec3(1.0f) - F) * (1.0f - m.metallic);
  return kD * m.albedo * Fd_Lambert<float>() + specular;
}

// Outgoing radiance at `position` with normal n (need not be unit) and unit direction to
// the eye v: the reflectance equation over all lights, plus ambient and emission.
inline glm::vec3 shade(const ShadingMaterial& m, std::span<const PreparedLight> lights, const glm::vec3& ambient,
                       const glm::vec3& position, const glm::vec3& n_in, const glm::vec3& v) {
  const glm::vec3 n = normalize_or(n_in, v);
  glm::vec3 lo(0.0f);
  for (const PreparedLight& light : lights) {
    const LightSample s = sample_light(light, position);
    const float NoL = glm::dot(n, s.to_light);
    if (!(NoL > 0.0f)) continue;
    lo += brdf(m, n, s.to_light, v) * s.radiance * NoL;
  }
  return ambient * m.albedo * m.ao + lo + m.emissive;
}

// The PBR shader for softpbr::raster: world-space position and normal as varyings, the
// reflectance equation per pixel. Alpha is 1.
struct PbrShader {
  using Vertex = MeshVertex;
  struct Varyings {
    glm::vec3 world_position;
    glm::vec3 normal;
    glm::vec2 uv;
  };

  glm::mat4 model{1.0f};
  glm::mat3 normal_matrix{1.0f};  // inverse transpose of model's upper 3×3
  glm::mat4 view_projection{1.0f};
  glm::vec3 eye{0.0f};
  glm::vec3 ambient{0.0f};
  ShadingMaterial material{};
  std::shared_ptr<const std::vector<PreparedLight>> lights;

  glm::vec4 vertex(const Vertex& in, Varyings& out) const {
    const glm::vec4 world = model * glm::vec4(in.position, 1.0f);
    out.world_position = glm::vec3(world);
    out.normal = normal_matrix * in.normal;
    out.uv = in.uv;
    return view_projection * world;
  }
  glm::vec4 fragment(const raster::Fragment<Varyings>& f) const {
    const glm::vec3 v = normalize_or(eye - f.v.world_position, glm::vec3(0.0f, 0.0f, 1.0f));
    const glm::vec3 color = shade(material, *lights, ambient, f.v.world_position, f.v.normal, v);
    return glm::vec4(color, 1.0f);
  }
};

}  // namespace softpbr::pbr
