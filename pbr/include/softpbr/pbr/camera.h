// softpbr/pbr/camera.h — view and projection matrices (GL conventions: right-handed view
// space looking down −z, clip z in [−w, w]).
//
// The projection uses the deterministic dmath::tan, so its bits are the same everywhere.
#pragma once

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

namespace softpbr::pbr {

// Perspective projection from a vertical field of view in radians, as glm::perspective.
glm::mat4 perspective(float fovy, float aspect, float near, float far);

// View matrix looking from `eye` at `target` with `up` roughly up, as glm::lookAt.
glm::mat4 look_at(glm::vec3 eye, glm::vec3 target, glm::vec3 up);

}  // namespace softpbr::pbr
