// Punctual lights (see light.h).
#include "softpbr/pbr/light.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <glm/geometric.hpp>

#include "softpbr/dmath/dmath.h"

namespace softpbr::pbr {

namespace {
void require(bool ok, const char* field, const char* what) {
  if (!ok) throw std::invalid_argument(std::string("light ") + field + ": " + what);
}
bool finite3(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
}  // namespace

PreparedLight prepare_light(const Light& light) {
  require(finite3(light.position), "position", "must be finite");
  require(finite3(light.direction), "direction", "must be finite");
  require(finite3(light.color) && light.color.r >= 0 && light.color.g >= 0 && light.color.b >= 0, "color",
          "must be finite and non-negative");
  require(std::isfinite(light.intensity) && light.intensity >= 0, "intensity", "must be finite and >= 0");
  require(std::isfinite(light.range) && light.range >= 0, "range", "must be finite and >= 0 (0 = unlimited)");
  PreparedLight p{light, {0, -1, 0}, 0.0f, 1.0f, light.color * light.intensity};
  if (light.type != LightType::Point) {
    const float len2 = glm::dot(light.direction, light.direction);
    require(len2 > 0.0f, "direction", "must not be zero");
    p.unit_direction = light.direction / std::sqrt(len2);
  }
  if (light.type == LightType::Spot) {
    require(std::isfinite(light.inner_cone) && std::isfinite(light.outer_cone) && light.inner_cone >= 0 &&
                light.outer_cone > 0 && light.outer_cone <= 1.5707963267948966f,
            "outer_cone", "must be in (0, pi/2] radians, with inner_cone >= 0");
    require(light.inner_cone <= light.outer_cone, "inner_cone", "must not exceed outer_cone");
    // KHR_lights_punctual: attenuation = saturate(cd · scale + offset)², cd = cos of the angle.
    const float cos_outer = static_cast<float>(dmath::cos(light.outer_cone));
    const float cos_inner = static_cast<float>(dmath::cos(light.inner_cone));
    p.cone_scale = 1.0f / std::max(0.001f, cos_inner - cos_outer);
    p.cone_offset = -cos_outer * p.cone_scale;
  }
  return p;
}

}  // namespace softpbr::pbr
