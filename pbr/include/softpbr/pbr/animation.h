// softpbr/pbr/animation.h — the turntable animation of scene files and `softpbr render
// --frames`: the camera orbits its target and the lights turn about a vertical axis.
#pragma once

#include <glm/vec3.hpp>

#include "softpbr/pbr/scene.h"

namespace softpbr::pbr {

// The turntable animation applied by animate(): at frame f the camera turns by
// f · camera_degrees_per_frame about the vertical axis through its target, and every light
// by f · light_degrees_per_frame about the vertical axis through light_pivot.
struct Animation {
  double camera_degrees_per_frame = 3.0;  // a full turn in 120 frames
  double light_degrees_per_frame = 6.0;   // the lights go round twice as fast
  glm::vec3 light_pivot{0.0f, 0.0f, 0.0f};
};

// The scene at frame `frame` (frame 0 is `scene` as it is; negative frames turn the other
// way). Angles are reduced modulo 360° exactly and go through dmath, so every frame has
// the same bits on every platform.
Scene animate(const Scene& scene, const Animation& animation, long frame);

}  // namespace softpbr::pbr
