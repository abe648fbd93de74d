// Scene files: the camera, a look-at or an orbit camera (see scene_file/loader.h).
#include "loader.h"

#include "softpbr/dmath/dmath.h"

namespace softpbr::pbr::scene_file {

Camera read_camera(const Reader& r, const Node& spec) {
  Camera c;
  const bool orbit = spec.value.is_object() && spec.value.contains("distance");
  if (orbit) {
    r.object(spec, {"target", "distance", "yaw", "pitch", "fov", "near", "far"});
    OrbitCamera o;
    if (auto t = r.member(spec, "target")) o.target = r.vec3(*t);
    o.distance = r.number_f(r.required(spec, "distance"), 0, 1e18, true);  // validate(): < 1e19
    if (auto y = r.member(spec, "yaw")) o.yaw = static_cast<float>(dmath::radians(r.number(*y, -360, 360)));
    if (auto p = r.member(spec, "pitch")) o.pitch = static_cast<float>(dmath::radians(r.number(*p, -89, 89)));
    c = o.camera();
  } else {
    r.object(spec, {"position", "target", "up", "fov", "near", "far"});
    if (auto p = r.member(spec, "position")) c.position = r.vec3(*p);
    if (auto t = r.member(spec, "target")) c.target = r.vec3(*t);
    if (auto u = r.member(spec, "up")) c.up = r.vec3(*u);
  }
  if (auto f = r.member(spec, "fov")) c.fovy = static_cast<float>(dmath::radians(r.number(*f, 0, 180, true, true)));
  if (auto n = r.member(spec, "near")) c.near = r.number_f(*n, 0, 1e30, true);
  if (auto f = r.member(spec, "far")) c.far = r.number_f(*f, 0, 1e30, true);
  check_at(r, spec, [&] { validate(c); });
  return c;
}

}  // namespace softpbr::pbr::scene_file
