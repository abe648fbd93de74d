// The glTF reader's material extensions (see materials.h): KHR_materials_ior,
// KHR_materials_specular, KHR_materials_clearcoat, KHR_materials_sheen,
// KHR_materials_anisotropy, KHR_materials_iridescence, KHR_materials_transmission,
// KHR_materials_volume and KHR_materials_dispersion, each to its
// ratified specification (KhronosGroup/glTF, extensions/2.0/Khronos/), into the layers of
// pbr::Material. Factors must be finite numbers (else an error at their JSON pointer) and
// are clamped to their ranges, as the core material's are.
//
// The archived KHR_materials_pbrSpecularGlossiness (extensions/2.0/Archived/) is converted
// at load time into those layers: a dielectric (metallic 0) of
// base colour and alpha = diffuse, roughness = 1 − glossiness, and F0 = the specular colour,
// written as KHR_materials_ior 0 (F0(ior) = 1, brdf.h's f0_from_ior) with KHR_materials_specular's
// colour = specularFactor × the specular-glossiness texture's RGB (sRGB), so F0 = min(1 · specular, 1).
// The texture's glossiness (A) becomes a roughness texture made at load time (a roughness
// slot reads G × factor, not 1 − A): materials.cpp, roughness_from_glossiness.
// docs/design.md, "glTF", gives the differences from the specification.
#include <algorithm>
#include <cmath>
#include <string>

#include <glm/vec4.hpp>

#include "gltf/materials.h"

namespace softpbr::pbr::gltf {

namespace {
using CS = raster::ColorSpace;
}  // namespace

void Materials::extension_texture(TextureSlot& slot, const tg::Value& info, raster::ColorSpace space,
                                  const std::string& pointer, float* scale) {
  if (!info.IsObject()) fail(pointer, "expected a textureInfo object");
  if (!info.Has("index") || !info.Get("index").IsInt()) fail(pointer + "/index", "expected a texture index");
  int tex_coord = 0;
  if (info.Has("texCoord")) {
    if (!info.Get("texCoord").IsInt() || info.Get("texCoord").GetNumberAsInt() < 0)
      fail(pointer + "/texCoord", "expected an integer ≥ 0");
    tex_coord = info.Get("texCoord").GetNumberAsInt();
  }
  if (scale != nullptr && info.Has("scale")) {
    const tg::Value& v = info.Get("scale");
    if (!v.IsNumber() || !std::isfinite(v.GetNumberAsDouble())) fail(pointer + "/scale", "expected a finite number");
    *scale = static_cast<float>(v.GetNumberAsDouble());
  }
  tg::ExtensionMap extensions;
  if (info.Has("extensions")) {
    const tg::Value& e = info.Get("extensions");
    if (!e.IsObject()) fail(pointer + "/extensions", "expected an object");
    for (const std::string& key : e.Keys()) extensions[key] = e.Get(key);
  }
  texture_slot(slot, info.Get("index").GetNumberAsInt(), tex_coord, extensions, space, pointer);
}

void Materials::layers(Material& m, const tg::Material& g, const std::string& pointer) {
  // A number of extension `x` at key `key`, finite, clamped to [lo, hi]; `fallback` when absent.
  const auto number = [&](const tg::Value& x, const std::string& xp, const char* key, double fallback, double lo,
                          double hi) {
    if (!x.Has(key)) return static_cast<float>(fallback);
    const tg::Value& v = x.Get(key);
    if (!v.IsNumber() || !std::isfinite(v.GetNumberAsDouble())) fail(xp + "/" + key, "expected a finite number");
    return static_cast<float>(std::clamp(v.GetNumberAsDouble(), lo, hi));
  };
  const auto color = [&](const tg::Value& x, const std::string& xp, const char* key, glm::vec3 fallback, double hi) {
    if (!x.Has(key)) return fallback;
    const tg::Value& v = x.Get(key);
    if (!v.IsArray() || v.ArrayLen() != 3) fail(xp + "/" + key, "expected three numbers");
    glm::vec3 c;
    for (int i = 0; i < 3; ++i) {
      const tg::Value& e = v.Get(i);
      if (!e.IsNumber() || !std::isfinite(e.GetNumberAsDouble()))
        fail(xp + "/" + key + "/" + std::to_string(i), "expected a finite number");
      c[i] = static_cast<float>(std::clamp(e.GetNumberAsDouble(), 0.0, hi));
    }
    return c;
  };
  const auto texture = [&](TextureSlot& slot, const tg::Value& x, const std::string& xp, const char* key, CS space,
                           float* scale = nullptr) {
    if (x.Has(key)) extension_texture(slot, x.Get(key), space, xp + "/" + key, scale);
  };
  const auto extension = [&](const char* name, std::string& xp) -> const tg::Value* {
    const auto it = g.extensions.find(name);
    if (it == g.extensions.end()) return nullptr;
    xp = pointer + "/extensions/" + name;
    if (!it->second.IsObject()) fail(xp, "expected an object");
    return &it->second;
  };
  std::string xp;
  if (const tg::Value* x = extension(kSpecularGlossiness, xp)) {
    // Replaces the metal/roughness values (whose textures material() then does not read),
    // and KHR_materials_ior and _specular, which are not read beside it.
    glm::vec4 diffuse(1.0f);
    if (x->Has("diffuseFactor")) {
      const tg::Value& v = x->Get("diffuseFactor");
      if (!v.IsArray() || v.ArrayLen() != 4) fail(xp + "/diffuseFactor", "expected four numbers");
      for (int i = 0; i < 4; ++i) {
        const tg::Value& e = v.Get(i);
        if (!e.IsNumber() || !std::isfinite(e.GetNumberAsDouble()))
          fail(xp + "/diffuseFactor/" + std::to_string(i), "expected a finite number");
        diffuse[i] = static_cast<float>(std::clamp(e.GetNumberAsDouble(), 0.0, 1.0));
      }
    }
    m.base_color = glm::vec3(diffuse);
    m.alpha = diffuse.a;
    m.metallic = 0.0f;
    const float glossiness = number(*x, xp, "glossinessFactor", 1.0, 0.0, 1.0);
    m.roughness = 1.0f - glossiness;
    m.ior = 0.0f;
    m.specular = Specular{};
    m.specular.color = color(*x, xp, "specularFactor", glm::vec3(1.0f), 1.0);
    texture(m.base_color_texture, *x, xp, "diffuseTexture", CS::Srgb);
    texture(m.specular.color_texture, *x, xp, "specularGlossinessTexture", CS::Srgb);
    // The glossiness in the same texture's alpha: roughness = 1 − glossinessFactor · A, in
    // the metal/roughness slot (G × roughness) as a texture made from the image at the end
    // (make_textures), G = 255 − round(glossinessFactor · A), and the roughness factor 1.
    const std::size_t queued = pending_.size();
    texture(m.metallic_roughness_texture, *x, xp, "specularGlossinessTexture", CS::Linear);
    if (pending_.size() != queued) {
      pending_.back().glossiness = glossiness;
      m.roughness = 1.0f;
    }
  } else {
    if (const tg::Value* x = extension("KHR_materials_ior", xp)) {
      if (x->Has("ior")) {
        const tg::Value& v = x->Get("ior");
        const double ior = v.IsNumber() ? v.GetNumberAsDouble() : -1.0;
        if (!(ior == 0.0 || (ior >= 1.0 && std::isfinite(ior)))) fail(xp + "/ior", "must be 0 or a finite number ≥ 1");
        m.ior = static_cast<float>(ior);
      }
    }
    if (const tg::Value* x = extension("KHR_materials_specular", xp)) {
      m.specular.factor = number(*x, xp, "specularFactor", 1.0, 0.0, 1.0);
      texture(m.specular.texture, *x, xp, "specularTexture", CS::Linear);
      // The colour may exceed 1 (the specification: F0 = min(F0(ior) · colour, 1)).
      m.specular.color = color(*x, xp, "specularColorFactor", glm::vec3(1.0f), 1e30);
      texture(m.specular.color_texture, *x, xp, "specularColorTexture", CS::Srgb);
    }
  }
  if (const tg::Value* x = extension("KHR_materials_clearcoat", xp)) {
    m.clearcoat.factor = number(*x, xp, "clearcoatFactor", 0.0, 0.0, 1.0);
    texture(m.clearcoat.texture, *x, xp, "clearcoatTexture", CS::Linear);
    m.clearcoat.roughness = number(*x, xp, "clearcoatRoughnessFactor", 0.0, 0.0, 1.0);
    texture(m.clearcoat.roughness_texture, *x, xp, "clearcoatRoughnessTexture", CS::Linear);
    texture(m.clearcoat.normal_texture, *x, xp, "clearcoatNormalTexture", CS::Linear, &m.clearcoat.normal_scale);
  }
  if (const tg::Value* x = extension("KHR_materials_sheen", xp)) {
    m.sheen.color = color(*x, xp, "sheenColorFactor", glm::vec3(0.0f), 1.0);
    texture(m.sheen.color_texture, *x, xp, "sheenColorTexture", CS::Srgb);
    m.sheen.roughness = number(*x, xp, "sheenRoughnessFactor", 0.0, 0.0, 1.0);
    texture(m.sheen.roughness_texture, *x, xp, "sheenRoughnessTexture", CS::Linear);
  }
  if (const tg::Value* x = extension("KHR_materials_anisotropy", xp)) {
    m.anisotropy.strength = number(*x, xp, "anisotropyStrength", 0.0, 0.0, 1.0);
    m.anisotropy.rotation = number(*x, xp, "anisotropyRotation", 0.0, -1e6, 1e6);
    texture(m.anisotropy.texture, *x, xp, "anisotropyTexture", CS::Linear);
  }
  if (const tg::Value* x = extension("KHR_materials_iridescence", xp)) {
    m.iridescence.factor = number(*x, xp, "iridescenceFactor", 0.0, 0.0, 1.0);
    texture(m.iridescence.texture, *x, xp, "iridescenceTexture", CS::Linear);
    m.iridescence.ior = number(*x, xp, "iridescenceIor", 1.3, 1.0, 1e6);
    m.iridescence.thickness_min = number(*x, xp, "iridescenceThicknessMinimum", 100.0, 0.0, 1e6);
    m.iridescence.thickness_max = number(*x, xp, "iridescenceThicknessMaximum", 400.0, 0.0, 1e6);
    texture(m.iridescence.thickness_texture, *x, xp, "iridescenceThicknessTexture", CS::Linear);
  }
  if (const tg::Value* x = extension("KHR_materials_transmission", xp)) {
    m.transmission.factor = number(*x, xp, "transmissionFactor", 0.0, 0.0, 1.0);
    texture(m.transmission.texture, *x, xp, "transmissionTexture", CS::Linear);
  }
  if (const tg::Value* x = extension("KHR_materials_volume", xp)) {
    // The thickness in the mesh's coordinates (≥ 0; 0: thin-walled); the attenuation
    // distance > 0, +∞ (no attenuation) when absent — JSON has no infinity, so a present
    // value must be a finite number above 0.
    m.volume.thickness = number(*x, xp, "thicknessFactor", 0.0, 0.0, 1e30);
    texture(m.volume.thickness_texture, *x, xp, "thicknessTexture", CS::Linear);
    if (x->Has("attenuationDistance")) {
      const tg::Value& v = x->Get("attenuationDistance");
      const double distance = v.IsNumber() ? v.GetNumberAsDouble() : -1.0;
      if (!(distance > 0.0 && std::isfinite(distance) && static_cast<float>(distance) > 0.0f))
        fail(xp + "/attenuationDistance", "must be a finite number > 0");
      m.volume.attenuation_distance = static_cast<float>(std::min(distance, 1e30));
    }
    m.volume.attenuation_color = color(*x, xp, "attenuationColor", glm::vec3(1.0f), 1.0);
  }
  if (const tg::Value* x = extension("KHR_materials_dispersion", xp))
    m.dispersion = number(*x, xp, "dispersion", 0.0, 0.0, 1e6);
}

}  // namespace softpbr::pbr::gltf
