// The glTF reader's animations (glTF 2.0 §3.11): samplers read and checked, sampled at one
// moment into a pose (node translation, rotation, scale and morph weights) that the scene
// graph composes instead of the nodes' own values. All in double with dmath, so a pose has
// the same bits everywhere. Private to the glTF reader (docs/design.md, "Animation and
// deformation").
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include <glm/gtc/quaternion.hpp>
#include <glm/vec3.hpp>

#include "gltf/reader.h"
#include "gltf/resources.h"

namespace softpbr::pbr::gltf {

enum class Interpolation { Step, Linear, CubicSpline };

// One sampler's keys: `times` strictly increasing and finite; `values` holds `width`
// numbers per key (CUBICSPLINE: three groups per key — in-tangent, value, out-tangent).
struct Curve {
  Interpolation interpolation = Interpolation::Linear;
  std::vector<float> times;
  std::vector<float> values;
  std::size_t width = 0;
};

// The curve's `width` values at time `t` (seconds) into `out`: before the first key the
// first value, after the last the last (clamped). STEP holds a key's value until the next;
// LINEAR interpolates straight, or, with `quaternion`, by slerp along the shorter arc;
// CUBICSPLINE is the specification's Hermite spline (Appendix C) with the tangents scaled
// by the key interval. A quaternion result is normalised. `curve` must be valid (as
// Animations reads it).
void sample(const Curve& curve, double t, bool quaternion, double* out);

// slerp(a, b, u) of unit quaternions along the shorter arc (glTF 2.0 Appendix C): with
// cos θ = a·b (b negated when negative), a·sin((1−u)θ)/sin θ + b·sin(uθ)/sin θ; when the
// two are nearly equal (cos θ > 0.9995) the normalised straight line, which then differs
// from it by less than 1e-7. θ by dmath::atan2, sines by dmath.
glm::dquat slerp(const glm::dquat& a, glm::dquat b, double u);

// What the animations set on one node at the chosen moment (each unset part keeps the
// node's own value).
struct NodePose {
  std::optional<glm::dvec3> translation, scale;
  std::optional<glm::dquat> rotation;
  std::optional<std::vector<double>> weights;
};

// An animation as `softpbr info` lists it.
struct AnimationSummary {
  std::string name;
  double duration = 0.0;  // its last key time over all its samplers (seconds)
  std::size_t channels = 0;
};

class Animations : public Context {
 public:
  Animations(const Context& context, const Resources& resources) : Context(context), resources_(resources) {}

  // Every animation's name, duration and channel count (every sampler's input read and
  // checked).
  std::vector<AnimationSummary> summaries() const;

  // The pose at options_.time of the animation options_.animation names (an index or a
  // name; empty: every animation, applied in the file's order), one entry per node; empty
  // when options_.time is not set and no animation is named (the file's own transforms).
  // Throws LoadError for anything the specification forbids in what it samples.
  std::vector<NodePose> pose() const;

 private:
  int chosen() const;  // -1: all
  Curve curve(std::size_t animation, int sampler, const std::string& pointer, std::size_t width, bool weights) const;
  std::size_t morph_target_count(int node) const;
  void check_memory() const;

  const Resources& resources_;
};

}  // namespace softpbr::pbr::gltf
