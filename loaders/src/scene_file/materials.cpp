// Scene files: materials, a preset name or an object of overrides and textures (see
// scene_file/loader.h).
#include "loader.h"

namespace softpbr::pbr::scene_file {

Material read_material(const Reader& r, const Node& spec, TextureLibrary& textures) {
  if (spec.value.is_string()) {
    const auto preset = material_preset(spec.value.get<std::string>());
    if (!preset) {
      std::vector<std::string> names;
      for (const NamedMaterial& m : material_presets()) names.emplace_back(m.name);
      r.choice(spec, names);  // fails with the list of presets
    }
    return *preset;
  }
  r.object(spec, {"preset", "base_color", "metallic", "roughness", "ao", "emissive", "alpha", "alpha_mode",
                  "alpha_cutoff", "double_sided", "base_color_texture", "metallic_roughness_texture",
                  "normal_texture", "normal_scale", "occlusion_texture", "occlusion_strength", "emissive_texture",
                  "ior", "specular", "clearcoat", "sheen", "anisotropy", "iridescence", "transmission", "volume", "dispersion"});
  Material m;
  if (auto p = r.member(spec, "preset")) {
    if (!p->value.is_string()) r.fail(*p, "expected a preset name, got " + json_reader::show(p->value));
    m = read_material(r, *p, textures);
  }
  if (auto c = r.member(spec, "base_color")) m.base_color = r.vec3(*c, 0, 1);
  if (auto c = r.member(spec, "metallic")) m.metallic = r.number_f(*c, 0, 1);
  if (auto c = r.member(spec, "roughness")) m.roughness = r.number_f(*c, 0, 1);
  if (auto c = r.member(spec, "ao")) m.ao = r.number_f(*c, 0, 1);
  if (auto c = r.member(spec, "emissive")) m.emissive = r.vec3(*c, 0, 1e30);
  if (auto c = r.member(spec, "alpha")) m.alpha = r.number_f(*c, 0, 1);
  if (auto c = r.member(spec, "alpha_mode")) {
    const std::string mode = r.choice(*c, {"opaque", "mask", "blend"});
    m.alpha_mode = mode == "opaque" ? AlphaMode::Opaque : mode == "mask" ? AlphaMode::Mask : AlphaMode::Blend;
  }
  if (auto c = r.member(spec, "alpha_cutoff")) m.alpha_cutoff = r.number_f(*c, 0, 1);
  if (auto c = r.member(spec, "double_sided")) m.double_sided = r.boolean(*c);
  if (auto c = r.member(spec, "normal_scale")) m.normal_scale = r.number_f(*c, -1e30, 1e30);
  if (auto c = r.member(spec, "occlusion_strength")) m.occlusion_strength = r.number_f(*c, 0, 1);
  // Colour textures hold sRGB codes, data textures linear ones (glTF 2.0 §3.9.2).
  using raster::ColorSpace;
  if (auto t = r.member(spec, "base_color_texture")) m.base_color_texture = textures.slot(*t, ColorSpace::Srgb);
  if (auto t = r.member(spec, "metallic_roughness_texture"))
    m.metallic_roughness_texture = textures.slot(*t, ColorSpace::Linear);
  if (auto t = r.member(spec, "normal_texture")) m.normal_texture = textures.slot(*t, ColorSpace::Linear);
  if (auto t = r.member(spec, "occlusion_texture")) m.occlusion_texture = textures.slot(*t, ColorSpace::Linear);
  if (auto t = r.member(spec, "emissive_texture")) m.emissive_texture = textures.slot(*t, ColorSpace::Srgb);
  // The material extensions' layers (KHR_materials_ior, _specular, _clearcoat, _sheen).
  if (auto c = r.member(spec, "ior")) {
    m.ior = r.number_f(*c, 0, 1e30);
    if (m.ior != 0.0f && m.ior < 1.0f) r.fail(*c, "expected 0 or a number ≥ 1");
  }
  if (auto s = r.member(spec, "specular")) {
    r.object(*s, {"factor", "texture", "color", "color_texture"});
    if (auto c = r.member(*s, "factor")) m.specular.factor = r.number_f(*c, 0, 1);
    if (auto c = r.member(*s, "color")) m.specular.color = r.vec3(*c, 0, 1e30);
    if (auto t = r.member(*s, "texture")) m.specular.texture = textures.slot(*t, ColorSpace::Linear);
    if (auto t = r.member(*s, "color_texture")) m.specular.color_texture = textures.slot(*t, ColorSpace::Srgb);
  }
  if (auto s = r.member(spec, "clearcoat")) {
    r.object(*s, {"factor", "texture", "roughness", "roughness_texture", "normal_texture", "normal_scale"});
    if (auto c = r.member(*s, "factor")) m.clearcoat.factor = r.number_f(*c, 0, 1);
    if (auto c = r.member(*s, "roughness")) m.clearcoat.roughness = r.number_f(*c, 0, 1);
    if (auto c = r.member(*s, "normal_scale")) m.clearcoat.normal_scale = r.number_f(*c, -1e30, 1e30);
    if (auto t = r.member(*s, "texture")) m.clearcoat.texture = textures.slot(*t, ColorSpace::Linear);
    if (auto t = r.member(*s, "roughness_texture")) m.clearcoat.roughness_texture = textures.slot(*t, ColorSpace::Linear);
    if (auto t = r.member(*s, "normal_texture")) m.clearcoat.normal_texture = textures.slot(*t, ColorSpace::Linear);
  }
  if (auto s = r.member(spec, "sheen")) {
    r.object(*s, {"color", "color_texture", "roughness", "roughness_texture"});
    if (auto c = r.member(*s, "color")) m.sheen.color = r.vec3(*c, 0, 1);
    if (auto c = r.member(*s, "roughness")) m.sheen.roughness = r.number_f(*c, 0, 1);
    if (auto t = r.member(*s, "color_texture")) m.sheen.color_texture = textures.slot(*t, ColorSpace::Srgb);
    if (auto t = r.member(*s, "roughness_texture")) m.sheen.roughness_texture = textures.slot(*t, ColorSpace::Linear);
  }
  if (auto s = r.member(spec, "anisotropy")) {
    r.object(*s, {"strength", "rotation", "texture"});
    if (auto c = r.member(*s, "strength")) m.anisotropy.strength = r.number_f(*c, 0, 1);
    if (auto c = r.member(*s, "rotation")) m.anisotropy.rotation = r.number_f(*c, -1e6, 1e6);
    if (auto t = r.member(*s, "texture")) m.anisotropy.texture = textures.slot(*t, ColorSpace::Linear);
  }
  if (auto s = r.member(spec, "iridescence")) {
    r.object(*s, {"factor", "texture", "ior", "thickness_min", "thickness_max", "thickness_texture"});
    if (auto c = r.member(*s, "factor")) m.iridescence.factor = r.number_f(*c, 0, 1);
    if (auto c = r.member(*s, "ior")) m.iridescence.ior = r.number_f(*c, 1, 1e6);
    if (auto c = r.member(*s, "thickness_min")) m.iridescence.thickness_min = r.number_f(*c, 0, 1e6);
    if (auto c = r.member(*s, "thickness_max")) m.iridescence.thickness_max = r.number_f(*c, 0, 1e6);
    if (auto t = r.member(*s, "texture")) m.iridescence.texture = textures.slot(*t, ColorSpace::Linear);
    if (auto t = r.member(*s, "thickness_texture"))
      m.iridescence.thickness_texture = textures.slot(*t, ColorSpace::Linear);
  }
  if (auto s = r.member(spec, "transmission")) {
    r.object(*s, {"factor", "texture"});
    if (auto c = r.member(*s, "factor")) m.transmission.factor = r.number_f(*c, 0, 1);
    if (auto t = r.member(*s, "texture")) m.transmission.texture = textures.slot(*t, ColorSpace::Linear);
  }
  if (auto s = r.member(spec, "volume")) {
    r.object(*s, {"thickness", "thickness_texture", "attenuation_distance", "attenuation_color"});
    if (auto c = r.member(*s, "thickness")) m.volume.thickness = r.number_f(*c, 0, 1e30);
    if (auto c = r.member(*s, "attenuation_distance")) m.volume.attenuation_distance = r.number_f(*c, 0, 1e30, true);
    if (auto c = r.member(*s, "attenuation_color")) m.volume.attenuation_color = r.vec3(*c, 0, 1);
    if (auto t = r.member(*s, "thickness_texture")) m.volume.thickness_texture = textures.slot(*t, ColorSpace::Linear);
  }
  if (auto c = r.member(spec, "dispersion")) m.dispersion = r.number_f(*c, 0, 1e6);
  return m;
}

}  // namespace softpbr::pbr::scene_file
