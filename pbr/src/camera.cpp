// View and projection matrices.
#include "softpbr/pbr/camera.h"

#include <glm/gtc/matrix_transform.hpp>

#include "softpbr/raster/dmath.h"

namespace softpbr::pbr {

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

glm::mat4 look_at(glm::vec3 eye, glm::vec3 target, glm::vec3 up) {
  // glm::lookAt is basic arithmetic and sqrt only: deterministic as it is.
  return glm::lookAt(eye, target, up);
}

}  // namespace softpbr::pbr
