// Material validation for shading (see shading.h).
#include "softpbr/pbr/shading.h"

#include <stdexcept>
#include <string>

namespace softpbr::pbr {

namespace {
void require(bool ok, const char* field, const char* what) {
  if (!ok) throw std::invalid_argument(std::string("material ") + field + ": " + what);
}
bool in01(float x) { return x >= 0.0f && x <= 1.0f; }  // false for NaN
bool color_ok(const glm::vec3& c) {
  return std::isfinite(c.r) && std::isfinite(c.g) && std::isfinite(c.b) && c.r >= 0 && c.g >= 0 && c.b >= 0;
}
}  // namespace

ShadingMaterial prepare_material(const Material& m) {
  require(color_ok(m.base_color), "base_color", "must be finite and non-negative");
  require(color_ok(m.emissive), "emissive", "must be finite and non-negative");
  require(in01(m.metallic), "metallic", "must be a number in [0, 1]");
  require(in01(m.roughness), "roughness", "must be a number in [0, 1]");
  require(in01(m.ao), "ao", "must be a number in [0, 1]");
  ShadingMaterial s;
  s.albedo = m.base_color;
  s.f0 = f0_of(m.base_color, m.metallic);
  s.metallic = m.metallic;
  s.roughness = std::max(m.roughness, kMinRoughness);
  s.alpha = s.roughness * s.roughness;
  s.k = k_direct(s.roughness);
  s.ao = m.ao;
  s.emissive = m.emissive;
  return s;
}

}  // namespace softpbr::pbr
