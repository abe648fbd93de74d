// softpbr/pbr/material.h — metal/roughness materials and named presets with measured F0.
#pragma once

#include <optional>
#include <span>
#include <string_view>

#include <glm/vec3.hpp>

namespace softpbr::pbr {

// Perceptual roughness below this is raised to it before shading: α = r² = 0.002 keeps
// D_GGX's peak 1/(π α²) ≈ 8·10⁴ and its square inside float range (Filament uses the same
// floor, MIN_PERCEPTUAL_ROUGHNESS = 0.045, for fp32).
inline constexpr float kMinRoughness = 0.045f;

struct Material {
  glm::vec3 base_color{0.8f, 0.8f, 0.8f};  // linear; a metal's specular colour (F0)
  float metallic = 0.0f;                   // 0 dielectric … 1 metal
  float roughness = 0.5f;                  // perceptual, in [0, 1]
  float ao = 1.0f;                         // ambient occlusion, in [0, 1]
  glm::vec3 emissive{0.0f, 0.0f, 0.0f};    // linear radiance added as is
};

struct NamedMaterial {
  std::string_view name;
  Material material;
};

// All presets, metals first (see material.cpp for the source of every value).
std::span<const NamedMaterial> material_presets();

// The preset called `name` (e.g. "gold", "copper", "plastic_red"), if there is one.
std::optional<Material> material_preset(std::string_view name);

}  // namespace softpbr::pbr
