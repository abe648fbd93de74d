// The turntable animation (see animation.h).
#include "softpbr/pbr/animation.h"

#include <cmath>

#include "softpbr/dmath/dmath.h"

namespace softpbr::pbr {

namespace {
// `p` turned by `degrees` about the vertical axis through `pivot`, with dmath sine/cosine.
// Angles are reduced modulo 360 first (fmod is exact), so large frame numbers stay accurate.
glm::vec3 turn_about_y(glm::vec3 p, glm::vec3 pivot, double degrees) {
  const double a = dmath::radians(std::fmod(degrees, 360.0));
  const double c = dmath::cos(a), s = dmath::sin(a);
  const double x = static_cast<double>(p.x) - pivot.x, z = static_cast<double>(p.z) - pivot.z;
  // Right-handed turn about +y: x' = c·x + s·z, z' = −s·x + c·z.
  return {static_cast<float>(pivot.x + (c * x + s * z)), p.y, static_cast<float>(pivot.z + (c * z - s * x))};
}
glm::vec3 turn_direction(glm::vec3 d, double degrees) { return turn_about_y(d, glm::vec3(0.0f), degrees); }
}  // namespace

Scene animate(const Scene& scene, const Animation& animation, long frame) {
  Scene s = scene;
  if (frame == 0) return s;
  const double f = static_cast<double>(frame);
  const double cam = f * animation.camera_degrees_per_frame;
  if (cam != 0.0) {
    s.camera.position = turn_about_y(s.camera.position, s.camera.target, cam);
    s.camera.up = turn_direction(s.camera.up, cam);
  }
  const double lit = f * animation.light_degrees_per_frame;
  if (lit != 0.0)
    for (Light& l : s.lights) {
      l.position = turn_about_y(l.position, animation.light_pivot, lit);
      l.direction = turn_direction(l.direction, lit);
    }
  return s;
}

}  // namespace softpbr::pbr
