// softpbr/pbr/material.h — metal/roughness materials and named presets with measured F0.
#pragma once

#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <string_view>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "softpbr/raster/texture.h"

namespace softpbr::pbr {

// Perceptual roughness below this is raised to it before shading: α = r² = 0.002 keeps
// D_GGX's peak 1/(π α²) ≈ 8·10⁴ and its square inside float range (Filament uses the same
// floor, MIN_PERCEPTUAL_ROUGHNESS = 0.045, for fp32).
inline constexpr float kMinRoughness = 0.045f;

// A texture coordinate transform, as KHR_texture_transform: uv' = T(offset) · R(rotation)
// · S(scale) · uv, the rotation in radians, counter-clockwise in UV space (which turns the
// image clockwise on screen, v growing down).
struct UvTransform {
  glm::vec2 offset{0.0f, 0.0f};
  float rotation = 0.0f;
  glm::vec2 scale{1.0f, 1.0f};
};

// A material's texture: the image, how it is filtered, which UV set of the mesh it reads
// (0: MeshVertex::uv, 1: Mesh::uv1) and the transform applied to that UV first. An empty
// slot (no texture) costs nothing: the shader variant is chosen per draw.
struct TextureSlot {
  std::shared_ptr<const raster::Texture> texture;
  raster::Sampler sampler;
  int uv_set = 0;
  UvTransform transform;

  explicit operator bool() const { return texture != nullptr; }
};

// How alpha (base colour alpha × texture alpha) is used, as glTF's alphaMode: Opaque
// ignores it; Mask draws the pixels with alpha ≥ alpha_cutoff, opaque, and discards the
// rest; Blend composites premultiplied "over" what is behind, drawn after every opaque
// object, farthest first.
enum class AlphaMode : std::uint8_t { Opaque, Mask, Blend };

// The layers of glTF's material extensions (KHR_materials_*), each off at its defaults: a
// material whose layers are all off is drawn by the shaders of the core material, bit for
// bit as without them. Each factor multiplies its texture's channel named beside it.

// KHR_materials_clearcoat: a second GGX lobe of a dielectric coat (F0 0.04) over the
// material, which loses what the coat reflects (its Fresnel, times the factor).
struct Clearcoat {
  float factor = 0.0f;                  // in [0, 1]; 0: no coat
  TextureSlot texture;                  // linear R × factor
  float roughness = 0.0f;               // perceptual, in [0, 1]
  TextureSlot roughness_texture;        // linear G × roughness
  TextureSlot normal_texture;           // the coat's own normal map (else the geometric normal)
  float normal_scale = 1.0f;
};

// KHR_materials_sheen: the "Charlie" sheen of Estevez & Kulla 2017 over the material, which
// is scaled by 1 − max(colour) · E(n·v) (the sheen's directional albedo).
struct Sheen {
  glm::vec3 color{0.0f, 0.0f, 0.0f};    // linear; black: no sheen
  TextureSlot color_texture;            // RGB (sRGB colour) × color
  float roughness = 0.0f;               // perceptual, in [0, 1]
  TextureSlot roughness_texture;        // linear A × roughness
};

// KHR_materials_specular: the strength and the F0 colour of the dielectric's reflection.
struct Specular {
  float factor = 1.0f;                  // in [0, 1]: scales F0 and F90 of the dielectric
  TextureSlot texture;                  // linear A × factor
  glm::vec3 color{1.0f, 1.0f, 1.0f};    // linear, ≥ 0: F0 = min(F0(ior) · colour, 1)
  TextureSlot color_texture;            // RGB (sRGB colour) × color
};

// KHR_materials_anisotropy: the GGX lobe rougher along one direction of the surface,
// α_t = mix(α, 1, strength²) along it and α_b = α across it (α = roughness²).
struct Anisotropy {
  float strength = 0.0f;                // in [0, 1]; 0: isotropic
  float rotation = 0.0f;                // radians, counter-clockwise from the tangent
  TextureSlot texture;                  // linear RG: direction (×2 − 1) in the tangent frame,
                                        // then rotated; B × strength
};

// KHR_materials_iridescence: a thin film over the material whose interference colours its
// Fresnel reflectance (Belcour & Barla 2017, as the extension gives it).
struct Iridescence {
  float factor = 0.0f;                  // in [0, 1]; 0: no film
  TextureSlot texture;                  // linear R × factor
  float ior = 1.3f;                     // the film's index of refraction, ≥ 1
  float thickness_min = 100.0f;         // nanometres, ≥ 0
  float thickness_max = 400.0f;         // nanometres, ≥ 0: the thickness without a texture
  TextureSlot thickness_texture;        // linear G: mix(min, max, G)
};

// KHR_materials_transmission: the fraction of light the dielectric lets through (thin,
// optically clear: glass, water, plastic film), instead of scattering it diffusely. Drawn
// after the opaque objects, reading what they left on screen (docs/design.md, "Shading").
struct Transmission {
  float factor = 0.0f;                  // in [0, 1]; 0: opaque (no transmission)
  TextureSlot texture;                  // linear R × factor
};

// KHR_materials_volume: the medium inside a transmissive surface. The thickness is in the
// mesh's own coordinates (the object's scale applies); 0 is a thin wall (no refraction
// offset, no attenuation). Light crossing a distance d is attenuated by Beer–Lambert:
// attenuation_color^(d / attenuation_distance) = exp(−σ d), σ = −ln(colour)/distance.
struct Volume {
  float thickness = 0.0f;               // ≥ 0, finite
  TextureSlot thickness_texture;        // linear G × thickness
  float attenuation_distance = std::numeric_limits<float>::infinity();  // > 0; +∞: none
  glm::vec3 attenuation_color{1.0f, 1.0f, 1.0f};                         // linear, in [0, 1]
};

// The metal/roughness material of glTF 2.0. Each factor multiplies its texture when the
// slot has one (the texture's linear value: colour textures are decoded from sRGB).
struct Material {
  glm::vec3 base_color{0.8f, 0.8f, 0.8f};  // linear; a metal's specular colour (F0)
  float metallic = 0.0f;                   // 0 dielectric … 1 metal
  float roughness = 0.5f;                  // perceptual, in [0, 1]
  float ao = 1.0f;                         // ambient occlusion, in [0, 1]
  glm::vec3 emissive{0.0f, 0.0f, 0.0f};    // linear radiance added as is
  float alpha = 1.0f;                      // base colour alpha, in [0, 1]
  AlphaMode alpha_mode = AlphaMode::Opaque;
  float alpha_cutoff = 0.5f;               // AlphaMode::Mask
  bool double_sided = false;               // drawn without culling; back faces flip the normal
  bool unlit = false;                      // KHR_materials_unlit: the base colour, no lighting

  TextureSlot base_color_texture;          // RGBA (sRGB colour) × (base_color, alpha)
  TextureSlot metallic_roughness_texture;  // linear: G × roughness, B × metallic (glTF)
  TextureSlot normal_texture;              // tangent-space normal map, linear RGB
  float normal_scale = 1.0f;               // scales the map's x and y
  TextureSlot occlusion_texture;           // linear R: ao = 1 + strength · (R − 1)
  float occlusion_strength = 1.0f;         // in [0, 1]
  TextureSlot emissive_texture;            // RGB (sRGB) × emissive

  // The material extensions' layers (see above) and KHR_materials_ior's index of
  // refraction: the dielectric's F0 = ((ior − 1) / (ior + 1))², 0.04 at 1.5; 0 (or +∞)
  // stands for F0 = 1, as the extension allows.
  float ior = 1.5f;
  Clearcoat clearcoat;
  Sheen sheen;
  Specular specular;
  Anisotropy anisotropy;
  Iridescence iridescence;
  Transmission transmission;
  Volume volume;  // read only with a transmission
  // KHR_materials_dispersion, read with a transmission and a volume: 20 / the Abbe number
  // (≥ 0; 0: none). The indices of red and blue become ior ∓ (ior − 1) · 0.025 · dispersion.
  float dispersion = 0.0f;

  // Whether any layer of the extensions is on: a coat or a sheen, or a dielectric F0 other
  // than the core material's 0.04 (an IOR other than 1.5, a specular factor or colour), an
  // anisotropy, a thin film or a transmission.
  bool layered() const {
    return clearcoat.factor != 0.0f || sheen.color != glm::vec3(0.0f) || ior != 1.5f || specular.factor != 1.0f ||
           specular.texture || specular.color != glm::vec3(1.0f) || specular.color_texture ||
           anisotropy.strength != 0.0f || iridescence.factor != 0.0f || transmissive();
  }
  // Whether the material transmits light (KHR_materials_transmission's factor above 0): it
  // is drawn after the opaque objects, over a copy of them.
  bool transmissive() const { return transmission.factor != 0.0f; }

  // Whether any slot holds a texture.
  bool textured() const {
    return base_color_texture || metallic_roughness_texture || normal_texture || occlusion_texture ||
           emissive_texture;
  }
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
