// Scene files: the camera, a look-at or an orbit camera (see scene_file/loader.h).
#include "loader.h"

#include <cmath>

#include "softpbr/dmath/dmath.h"

namespace softpbr::pbr::scene_file {

// The largest far/near a scene file's camera may have (docs/scene-format.md).
constexpr double kMaxDepthRange = 1e7;

Camera read_camera(const Reader& r, const Node& spec) {
  Camera c;
  const bool orbit = spec.value.is_object() && spec.value.contains("distance");
  if (orbit) {
    r.object(spec, {"target", "distance", "yaw", "pitch", "fov", "orthographic", "near", "far"});
    OrbitCamera o;
    if (auto t = r.member(spec, "target")) o.target = r.vec3(*t);
    o.distance = r.number_f(r.required(spec, "distance"), 0, 1e18, true);  // validate(): < 1e19
    if (auto y = r.member(spec, "yaw")) o.yaw = static_cast<float>(dmath::radians(r.number(*y, -360, 360)));
    if (auto p = r.member(spec, "pitch")) o.pitch = static_cast<float>(dmath::radians(r.number(*p, -89, 89)));
    c = o.camera();
  } else {
    r.object(spec, {"position", "target", "up", "fov", "orthographic", "near", "far"});
    if (auto p = r.member(spec, "position")) c.position = r.vec3(*p);
    if (auto t = r.member(spec, "target")) c.target = r.vec3(*t);
    if (auto u = r.member(spec, "up")) c.up = r.vec3(*u);
  }
  if (auto f = r.member(spec, "fov")) {
    // (0, 180) as documented: a fov within float precision of 180 degrees is the largest
    // float below pi (rounding to nearest would give float(pi), which is above pi).
    c.fovy = static_cast<float>(dmath::radians(r.number(*f, 0, 180, true, true)));
    if (!(static_cast<double>(c.fovy) < dmath::kPi)) c.fovy = std::nextafter(static_cast<float>(dmath::kPi), 0.0f);
    if (!(c.fovy > 0.0f)) r.fail(*f, "expected a number in (0, 180) in float precision, got " + json_reader::show(f->value));
  }
  if (auto o = r.member(spec, "orthographic")) {
    // glTF's orthographic camera: half the view's height (ymag) and width (xmag, default
    // ymag × the image's aspect ratio) in world units.
    if (auto f = r.member(spec, "fov")) r.fail(*f, "an orthographic camera has no field of view (its view is 2·ymag high)");
    r.object(*o, {"ymag", "xmag"});
    c.orthographic = true;
    c.ymag = r.number_f(r.required(*o, "ymag"), 0, 1e30, true);
    if (auto x = r.member(*o, "xmag")) c.xmag = r.number_f(*x, 0, 1e30, true);
  }
  if (auto n = r.member(spec, "near")) c.near = c.orthographic ? r.number_f(*n, 0, 1e30) : r.number_f(*n, 0, 1e30, true);
  if (auto f = r.member(spec, "far")) c.far = r.number_f(*f, 0, 1e30, true);
  check_at(r, spec, [&] { validate(c); });
  // The depth buffer holds z/w in float: beyond far/near = 1e7 the depths of a whole scene
  // round to a few values (near 1e-8 with far 100 rendered one flat colour).
  // (An orthographic camera's depth is linear in the distance: no such limit.)
  if (!c.orthographic && static_cast<double>(c.far) / static_cast<double>(c.near) > kMaxDepthRange)
    r.fail(r.member(spec, "near") ? *r.member(spec, "near") : spec,
           "far/near is " + json_reader::show_rounded(static_cast<double>(c.far) / c.near) + ", over " +
               json_reader::show_number(kMaxDepthRange) + " (the depth buffer's float precision would be lost: raise near)");
  return c;
}

}  // namespace softpbr::pbr::scene_file
