// Material presets. Metals: base colour = measured linear F0 at normal incidence,
// metallic 1. Dielectrics: F0 is the fixed 0.04 of the metal/roughness model; base colour
// is the diffuse albedo.
#include "softpbr/pbr/material.h"

#include <array>

namespace softpbr::pbr {

namespace {

Material metal(float r, float g, float b, float roughness = 0.3f) {
  Material m;
  m.base_color = {r, g, b};
  m.metallic = 1.0f;
  m.roughness = roughness;
  return m;
}
Material dielectric(float r, float g, float b, float roughness) {
  Material m;
  m.base_color = {r, g, b};
  m.roughness = roughness;
  return m;
}

// Built on first use (a Material holds texture handles, so it is not a literal type).
const std::array<NamedMaterial, 14>& presets() {
  static const std::array<NamedMaterial, 14> kPresets = {
    // Hoffman, "Physics and Math of Shading", SIGGRAPH 2010/2015 courses (also Real-Time
    // Rendering 3rd ed., Table 7.3): linear F0.
    NamedMaterial{"gold", metal(1.00f, 0.71f, 0.29f)},
    NamedMaterial{"copper", metal(0.95f, 0.64f, 0.54f)},
    NamedMaterial{"silver", metal(0.95f, 0.93f, 0.88f)},
    NamedMaterial{"aluminium", metal(0.91f, 0.92f, 0.92f)},
    NamedMaterial{"iron", metal(0.56f, 0.57f, 0.58f)},
    // Real-Time Rendering 4th ed., Table 9.2 (linear F0).
    NamedMaterial{"titanium", metal(0.542f, 0.497f, 0.449f)},
    NamedMaterial{"chromium", metal(0.549f, 0.556f, 0.554f)},
    NamedMaterial{"nickel", metal(0.660f, 0.609f, 0.526f)},
    NamedMaterial{"platinum", metal(0.673f, 0.637f, 0.585f)},
    // Dielectrics: F0 = 0.04 (RTR4 Table 9.1: plastics and glass 0.04–0.05). Albedos are
    // chosen, not measured: saturated plastic colours, black rubber (charcoal-dark albedo
    // ≈ 0.02–0.04 as in RTR4's albedo charts), white paint.
    NamedMaterial{"plastic_red", dielectric(0.8f, 0.1f, 0.1f, 0.3f)},
    NamedMaterial{"plastic_green", dielectric(0.1f, 0.6f, 0.15f, 0.3f)},
    NamedMaterial{"plastic_blue", dielectric(0.1f, 0.2f, 0.8f, 0.3f)},
    NamedMaterial{"rubber", dielectric(0.03f, 0.03f, 0.03f, 0.9f)},
    NamedMaterial{"white_paint", dielectric(0.8f, 0.8f, 0.8f, 0.6f)},
  };
  return kPresets;
}

}  // namespace

std::span<const NamedMaterial> material_presets() { return presets(); }

std::optional<Material> material_preset(std::string_view name) {
  for (const NamedMaterial& p : presets())
    if (p.name == name) return p.material;
  return std::nullopt;
}

}  // namespace softpbr::pbr
