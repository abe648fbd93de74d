// Scene files: point, directional and spot lights (see scene_file/loader.h).
#include "loader.h"

#include <algorithm>

#include "softpbr/dmath/dmath.h"

namespace softpbr::pbr::scene_file {

Light read_light(const Reader& r, const Node& spec) {
  r.object(spec, {"type", "position", "direction", "color", "intensity", "range", "inner_cone", "outer_cone", "shadows"});
  Light l;
  const std::string type = r.choice(r.required(spec, "type"), {"point", "directional", "spot"});
  l.type = type == "point" ? LightType::Point : type == "directional" ? LightType::Directional : LightType::Spot;
  auto only = [&](const char* key, bool allowed) -> std::optional<Node> {
    auto m = r.member(spec, key);
    if (m && !allowed) r.fail(*m, "a " + type + " light has no \"" + key + "\"");
    return m;
  };
  const bool positioned = l.type != LightType::Directional, aimed = l.type != LightType::Point;
  if (auto p = only("position", positioned)) l.position = r.vec3(*p);
  else if (positioned) r.required(spec, "position");
  if (auto d = only("direction", aimed)) {
    l.direction = r.vec3(*d);
    if (l.direction == glm::vec3(0.0f)) r.fail(*d, "expected a non-zero direction, got [0, 0, 0]");
  } else if (aimed) {
    r.required(spec, "direction");
  }
  if (auto c = r.member(spec, "color")) l.color = r.vec3(*c, 0, 1e30);
  if (auto i = r.member(spec, "intensity")) l.intensity = r.number_f(*i, 0, 1e30);
  // Each is at most 1e30, but their product is the radiance: it must stay well inside float.
  if (const double power = static_cast<double>(l.intensity) * std::max({l.color.r, l.color.g, l.color.b}); power > 1e30)
    r.fail(r.member(spec, "intensity") ? *r.member(spec, "intensity") : spec,
           "intensity x color is " + json_reader::show_rounded(power) +
               ", over 1e+30 (the light's radiance would overflow float: an all-black .hdr/.exr)");
  if (auto g = only("range", positioned)) l.range = r.number_f(*g, 0, 1e30);
  // Cone angles in degrees, from the spot's axis: 0 <= inner <= outer, 0 < outer <= 90.
  double inner = 0.0, outer = 45.0;
  std::optional<Node> outer_node = only("outer_cone", l.type == LightType::Spot);
  if (auto i = only("inner_cone", l.type == LightType::Spot)) inner = r.number(*i, 0, 90);
  if (outer_node) outer = r.number(*outer_node, 0, 90, true);
  if (inner > outer) r.fail(r.required(spec, "inner_cone"), "expected inner_cone <= outer_cone (" + json_reader::show_number(outer) + "), got " + json_reader::show_number(inner));
  l.inner_cone = static_cast<float>(dmath::radians(inner));
  l.outer_cone = static_cast<float>(dmath::radians(outer));
  if (auto s = r.member(spec, "shadows")) l.shadows = r.boolean(*s);
  check_at(r, spec, [&] { prepare_light(l); });
  return l;
}

}  // namespace softpbr::pbr::scene_file
