// Scene files: materials, a preset name or an object of overrides (see scene_file/loader.h).
#include "loader.h"

namespace softpbr::pbr::scene_file {

Material read_material(const Reader& r, const Node& spec) {
  if (spec.value.is_string()) {
    const auto preset = material_preset(spec.value.get<std::string>());
    if (!preset) {
      std::vector<std::string> names;
      for (const NamedMaterial& m : material_presets()) names.emplace_back(m.name);
      r.choice(spec, names);  // fails with the list of presets
    }
    return *preset;
  }
  r.object(spec, {"preset", "base_color", "metallic", "roughness", "ao", "emissive"});
  Material m;
  if (auto p = r.member(spec, "preset")) {
    if (!p->value.is_string()) r.fail(*p, "expected a preset name, got " + json_reader::show(p->value));
    m = read_material(r, *p);
  }
  if (auto c = r.member(spec, "base_color")) m.base_color = r.vec3(*c, 0, 1);
  if (auto c = r.member(spec, "metallic")) m.metallic = r.number_f(*c, 0, 1);
  if (auto c = r.member(spec, "roughness")) m.roughness = r.number_f(*c, 0, 1);
  if (auto c = r.member(spec, "ao")) m.ao = r.number_f(*c, 0, 1);
  if (auto c = r.member(spec, "emissive")) m.emissive = r.vec3(*c, 0, 1e30);
  return m;
}

}  // namespace softpbr::pbr::scene_file
