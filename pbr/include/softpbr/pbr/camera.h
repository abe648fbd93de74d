// softpbr/pbr/camera.h — cameras and their matrices (GL conventions: right-handed view
// space looking down −z, clip z in [−w, w]).
//
// Angles go through the deterministic dmath functions, so a camera gives the same matrix
// bits on every platform.
#pragma once

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

namespace softpbr::pbr {

// Perspective projection from a vertical field of view in radians, as glm::perspective.
glm::mat4 perspective(float fovy, float aspect, float near, float far);

// Orthographic projection as glTF 2.0 defines it (§3.10.3, "Projection matrices"): xmag
// and ymag are half the view's width and height in world units, near ≥ 0 and far > near
// its depth range:
//   | 1/xmag  0       0             0                      |
//   | 0       1/ymag  0             0                      |
//   | 0       0       2/(near−far)  (far+near)/(near−far)  |
//   | 0       0       0             1                      |
glm::mat4 orthographic(float xmag, float ymag, float near, float far);

// View matrix looking from `eye` at `target` with `up` roughly up, as glm::lookAt.
glm::mat4 look_at(glm::vec3 eye, glm::vec3 target, glm::vec3 up);

// A look-at camera: what a scene stores. Perspective by default, the aspect ratio coming
// from the target at render time; orthographic when `orthographic` is set, with rays
// parallel to the view direction (target − position): the view is 2·xmag × 2·ymag world
// units wherever the camera stands, and shading sees every point from that direction.
struct Camera {
  glm::vec3 position{0.0f, 0.0f, 3.0f};
  glm::vec3 target{0.0f, 0.0f, 0.0f};
  glm::vec3 up{0.0f, 1.0f, 0.0f};
  float fovy = 0.7853981633974483f;  // perspective: vertical field of view, radians (45°)
  float near = 0.1f;                 // orthographic: may be 0
  float far = 100.0f;
  bool orthographic = false;
  // Orthographic: half the view's height and width in world units (glTF's ymag, xmag).
  // xmag 0 follows the image: ymag × width / height. A glTF camera gives both, and a
  // target whose aspect differs from xmag / ymag stretches the image, as glTF's matrix does.
  float ymag = 1.0f;
  float xmag = 0.0f;

  glm::mat4 view() const { return look_at(position, target, up); }
  glm::mat4 projection(float aspect) const {
    return orthographic ? pbr::orthographic(xmag > 0.0f ? xmag : ymag * aspect, ymag, near, far)
                        : perspective(fovy, aspect, near, far);
  }
};

// Throws std::invalid_argument naming the field when the camera cannot make an image:
// non-finite values, position == target, up parallel to the view direction, far ≤ near;
// perspective: fovy outside (0, π), near ≤ 0; orthographic: near < 0, ymag ≤ 0, xmag < 0.
void validate(const Camera& camera);

// The fly camera of the paper's program (as LearnOpenGL's Camera class): yaw and pitch in
// radians, front = (sin yaw · cos pitch, sin pitch, −cos yaw · cos pitch), so yaw 0 looks
// down −z and positive yaw turns right. Pitch is kept within ±89°.
struct FlyCamera {
  glm::vec3 position{0.0f, 0.0f, 3.0f};
  float yaw = 0.0f;
  float pitch = 0.0f;
  float fovy = 0.7853981633974483f;
  float near = 0.1f;
  float far = 100.0f;

  glm::vec3 front() const;
  glm::vec3 right() const;  // normalize(front × world up)
  // Moves along front/right/world up by the given distances.
  void move(float forward, float rightward, float upward);
  // Turns by the given angles (radians), clamping pitch.
  void turn(float dyaw, float dpitch);
  Camera camera() const;
};

// An orbit (turntable) camera around `target`: yaw around the world y axis, pitch above
// the horizon, both in radians; yaw 0 puts the camera on +z looking towards −z.
struct OrbitCamera {
  glm::vec3 target{0.0f, 0.0f, 0.0f};
  float distance = 5.0f;
  float yaw = 0.0f;
  float pitch = 0.0f;
  float fovy = 0.7853981633974483f;
  float near = 0.1f;
  float far = 100.0f;

  glm::vec3 position() const;
  Camera camera() const;
};

}  // namespace softpbr::pbr
