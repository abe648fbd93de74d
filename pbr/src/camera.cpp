// Cameras and their matrices (see camera.h).
#include "softpbr/pbr/camera.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "softpbr/dmath/dmath.h"

namespace softpbr::pbr {

namespace {
float fsin(float x) { return static_cast<float>(dmath::sin(x)); }
float fcos(float x) { return static_cast<float>(dmath::cos(x)); }
constexpr float kMaxPitch = 1.5533430342749532f;  // 89° in radians
bool finite3(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
void require(bool ok, const char* field, const char* what) {
  if (!ok) throw std::invalid_argument(std::string("camera ") + field + ": " + what);
}
}  // namespace

glm::mat4 perspective(float fovy, float aspect, float near, float far) {
  const float f = static_cast<float>(1.0 / dmath::tan(0.5 * static_cast<double>(fovy)));
  glm::mat4 m(0.0f);
  m[0][0] = f / aspect;
  m[1][1] = f;
  m[2][2] = -(far + near) / (far - near);
  m[2][3] = -1.0f;
  m[3][2] = -(2.0f * far * near) / (far - near);
  return m;
}

glm::mat4 orthographic(float xmag, float ymag, float near, float far) {
  glm::mat4 m(0.0f);
  m[0][0] = 1.0f / xmag;
  m[1][1] = 1.0f / ymag;
  m[2][2] = 2.0f / (near - far);
  m[3][2] = (far + near) / (near - far);
  m[3][3] = 1.0f;
  return m;
}

glm::mat4 look_at(glm::vec3 eye, glm::vec3 target, glm::vec3 up) {
  // glm::lookAt is basic arithmetic and sqrt only: deterministic as it is.
  return glm::lookAt(eye, target, up);
}

void validate(const Camera& c) {
  require(finite3(c.position), "position", "must be finite");
  require(finite3(c.target), "target", "must be finite");
  require(finite3(c.up), "up", "must be finite");
  const glm::vec3 dir = c.target - c.position;
  require(glm::dot(dir, dir) > 0.0f, "target", "must differ from position");
  // The view matrix normalizes the view direction and up in float: their squared lengths
  // must not overflow (a camera 1e30 away was reported as "up parallel to the view").
  require(std::isfinite(glm::dot(dir, dir)), "position",
          "must be less than 1e19 from the target (the view matrix squares the distance in float)");
  require(std::isfinite(glm::dot(c.up, c.up)), "up", "must be shorter than 1e19 (its length is squared in float)");
  const glm::dvec3 d(dir), u(c.up), side = glm::cross(d, u);
  require(glm::dot(side, side) > 1e-12 * glm::dot(d, d) * glm::dot(u, u), "up",
          "must not be zero or parallel to the view direction");
  if (c.orthographic) {
    require(c.ymag > 0.0f && std::isfinite(c.ymag), "ymag", "must be finite and > 0");
    require(c.xmag >= 0.0f && std::isfinite(c.xmag), "xmag", "must be finite and > 0 (0: ymag times the aspect ratio)");
    // 1/xmag, 1/ymag and 2/(near − far) must stay finite in float.
    require(c.ymag >= 1e-30f, "ymag", "must be at least 1e-30");
    require(c.xmag == 0.0f || c.xmag >= 1e-30f, "xmag", "must be at least 1e-30");
    require(c.near >= 0.0f && std::isfinite(c.near), "near", "must be >= 0");
    require(c.far > c.near && std::isfinite(c.far), "far", "must be finite and > near");
    require(c.far - c.near >= 1e-30f, "far", "must be at least 1e-30 beyond near");
    require(std::isfinite(c.far + c.near), "far", "plus near must stay below 3.4e38 (float's range)");
    return;
  }
  require(c.fovy > 0.0f && static_cast<double>(c.fovy) < dmath::kPi, "fovy", "must be in (0, pi) radians");
  require(c.near > 0.0f && std::isfinite(c.near), "near", "must be > 0");
  require(c.far > c.near && std::isfinite(c.far), "far", "must be finite and > near");
}

glm::vec3 FlyCamera::front() const {
  const float cp = fcos(pitch);
  return {fsin(yaw) * cp, fsin(pitch), -fcos(yaw) * cp};
}

glm::vec3 FlyCamera::right() const { return glm::normalize(glm::cross(front(), glm::vec3(0.0f, 1.0f, 0.0f))); }

void FlyCamera::move(float forward, float rightward, float upward) {
  position += front() * forward + right() * rightward + glm::vec3(0.0f, upward, 0.0f);
}

void FlyCamera::turn(float dyaw, float dpitch) {
  yaw += dyaw;
  pitch = std::clamp(pitch + dpitch, -kMaxPitch, kMaxPitch);
}

Camera FlyCamera::camera() const {
  Camera c;
  c.position = position;
  c.target = position + front();
  c.up = {0.0f, 1.0f, 0.0f};
  c.fovy = fovy;
  c.near = near;
  c.far = far;
  return c;
}

glm::vec3 OrbitCamera::position() const {
  const float cp = fcos(pitch);
  return target + distance * glm::vec3(fsin(yaw) * cp, fsin(pitch), fcos(yaw) * cp);
}

Camera OrbitCamera::camera() const {
  Camera c;
  c.position = position();
  c.target = target;
  c.up = {0.0f, 1.0f, 0.0f};
  c.fovy = fovy;
  c.near = near;
  c.far = far;
  return c;
}

}  // namespace softpbr::pbr
