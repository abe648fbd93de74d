// The glTF reader's animations (see animation.h).
#include "gltf/animation.h"

#include <algorithm>
#include <cmath>

#include "softpbr/dmath/dmath.h"
#include "softpbr/loaders/format_bytes.h"

namespace softpbr::pbr::gltf {

namespace {

glm::dquat normalized(const glm::dquat& q) {
  const double len = std::sqrt(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w);
  if (!(len > 0.0)) return glm::dquat(1.0, 0.0, 0.0, 0.0);  // a zero quaternion: no rotation
  return glm::dquat(q.w / len, q.x / len, q.y / len, q.z / len);
}

// glTF stores quaternions (x, y, z, w); glm's constructor takes w first.
glm::dquat quat_at(const double* v) { return glm::dquat(v[3], v[0], v[1], v[2]); }

}  // namespace

glm::dquat slerp(const glm::dquat& a, glm::dquat b, double u) {
  double c = a.x * b.x + a.y * b.y + a.z * b.z + a.w * b.w;
  if (c < 0.0) {
    b = glm::dquat(-b.w, -b.x, -b.y, -b.z);
    c = -c;
  }
  if (c > 0.9995) {
    // Nearly equal: the straight line, normalised (θ < 0.032: its difference from the arc
    // is below θ²/8 · u(1−u) < 1.3e-4 · 0.25 in angle before normalising; after, < 1e-7).
    return normalized(glm::dquat(a.w + u * (b.w - a.w), a.x + u * (b.x - a.x), a.y + u * (b.y - a.y),
                                 a.z + u * (b.z - a.z)));
  }
  const double s = std::sqrt(std::max(0.0, 1.0 - c * c));
  const double theta = dmath::atan2(s, c);  // acos(c), from its sine and cosine
  const double sa = dmath::sin((1.0 - u) * theta) / s, sb = dmath::sin(u * theta) / s;
  return normalized(glm::dquat(sa * a.w + sb * b.w, sa * a.x + sb * b.x, sa * a.y + sb * b.y, sa * a.z + sb * b.z));
}

void sample(const Curve& curve, double t, bool quaternion, double* out) {
  const std::size_t keys = curve.times.size(), w = curve.width;
  const bool cubic = curve.interpolation == Interpolation::CubicSpline;
  // The value of key k (CUBICSPLINE: the middle of its three groups).
  auto value = [&](std::size_t k) { return curve.values.data() + (cubic ? (3 * k + 1) * w : k * w); };
  auto copy = [&](const float* v) {
    for (std::size_t c = 0; c < w; ++c) out[c] = v[c];
  };
  // Clamped outside the keys (§3.11: "before the first and after the last key").
  if (keys == 1 || !(t > curve.times.front())) {
    copy(value(0));
  } else if (t >= curve.times.back()) {
    copy(value(keys - 1));
  } else {
    // k: the last key at or before t (t lies inside [times[k], times[k + 1])).
    const std::size_t k =
        static_cast<std::size_t>(std::upper_bound(curve.times.begin(), curve.times.end(), t,
                                                  [](double x, float key) { return x < static_cast<double>(key); }) -
                                 curve.times.begin()) - 1;
    const double t0 = curve.times[k], t1 = curve.times[k + 1];
    const double td = t1 - t0;
    const double u = (t - t0) / td;
    switch (curve.interpolation) {
      case Interpolation::Step:
        copy(value(k));
        break;
      case Interpolation::Linear:
        if (quaternion) {
          double a[4], b[4];
          for (int c = 0; c < 4; ++c) {
            a[c] = value(k)[c];
            b[c] = value(k + 1)[c];
          }
          const glm::dquat q = slerp(normalized(quat_at(a)), normalized(quat_at(b)), u);
          out[0] = q.x, out[1] = q.y, out[2] = q.z, out[3] = q.w;
          return;
        }
        for (std::size_t c = 0; c < w; ++c) {
          const double a = value(k)[c], b = value(k + 1)[c];
          out[c] = a + u * (b - a);
        }
        break;
      case Interpolation::CubicSpline: {
        // glTF 2.0 Appendix C: p(u) = (2u³ − 3u² + 1)·v_k + td·(u³ − 2u² + u)·b_k
        //                            + (−2u³ + 3u²)·v_k+1 + td·(u³ − u²)·a_k+1,
        // a: in-tangents, b: out-tangents, td the key interval.
        const double u2 = u * u, u3 = u2 * u;
        const double h00 = 2.0 * u3 - 3.0 * u2 + 1.0, h10 = u3 - 2.0 * u2 + u, h01 = -2.0 * u3 + 3.0 * u2, h11 = u3 - u2;
        const float* vk = value(k);
        const float* bk = curve.values.data() + (3 * k + 2) * w;
        const float* vk1 = value(k + 1);
        const float* ak1 = curve.values.data() + (3 * (k + 1)) * w;
        for (std::size_t c = 0; c < w; ++c)
          out[c] = h00 * vk[c] + td * h10 * bk[c] + h01 * vk1[c] + td * h11 * ak1[c];
        break;
      }
    }
  }
  if (quaternion) {
    const glm::dquat q = normalized(quat_at(out));
    out[0] = q.x, out[1] = q.y, out[2] = q.z, out[3] = q.w;
  }
}

// ---- Reading -------------------------------------------------------------------------

int Animations::chosen() const {
  const std::string& a = options_.animation;
  if (a.empty()) return -1;
  const bool digits = std::all_of(a.begin(), a.end(), [](unsigned char c) { return c >= '0' && c <= '9'; });
  if (digits && a.size() <= 9) {
    const auto i = static_cast<std::size_t>(std::stoul(a));
    if (i >= m_.animations.size())
      fail("/animations", "the file has " + str(m_.animations.size()) + " animations, no animation " + a);
    return static_cast<int>(i);
  }
  for (std::size_t i = 0; i < m_.animations.size(); ++i)
    if (m_.animations[i].name == a) return static_cast<int>(i);
  fail("/animations", "no animation is named \"" + a + "\"");
}

std::size_t Animations::morph_target_count(int node) const {
  const tg::Node& n = m_.nodes[static_cast<std::size_t>(node)];
  if (n.mesh < 0 || static_cast<std::size_t>(n.mesh) >= m_.meshes.size()) return 0;
  const tg::Mesh& mesh = m_.meshes[static_cast<std::size_t>(n.mesh)];
  return mesh.primitives.empty() ? 0 : mesh.primitives.front().targets.size();
}

// Every key and value of the samplers about to be read, counted against the memory limit
// before any is read (a sparse accessor without a bufferView holds up to 2^28 zeros).
void Animations::check_memory() const {
  const int only = chosen();
  double bytes = 0.0;
  auto count = [&](int a) -> double {
    if (a < 0 || static_cast<std::size_t>(a) >= m_.accessors.size()) return 0.0;
    const tg::Accessor& x = m_.accessors[static_cast<std::size_t>(a)];
    const int comps = tg::GetNumComponentsInType(static_cast<std::uint32_t>(x.type));
    return static_cast<double>(x.count) * std::max(comps, 1) * 4.0;
  };
  for (std::size_t i = 0; i < m_.animations.size(); ++i) {
    if (only >= 0 && static_cast<std::size_t>(only) != i) continue;
    for (const tg::AnimationSampler& s : m_.animations[i].samplers) bytes += count(s.input) + count(s.output);
  }
  if (bytes > static_cast<double>(options_.memory_limit))
    fail(only >= 0 ? "/animations/" + std::to_string(only) : "/animations",
         "its samplers' keys need an estimated " + format_bytes(static_cast<std::uint64_t>(std::min(bytes, 1.8e19))) +
             ", over the memory limit of " + format_bytes(options_.memory_limit));
}

Curve Animations::curve(std::size_t animation, int sampler, const std::string& channel, std::size_t width,
                        bool weights) const {
  const tg::Animation& an = m_.animations[animation];
  const std::string ap = "/animations/" + str(animation);
  if (sampler < 0 || static_cast<std::size_t>(sampler) >= an.samplers.size())
    fail(channel + "/sampler", "sampler " + std::to_string(sampler) + " does not exist");
  const tg::AnimationSampler& s = an.samplers[static_cast<std::size_t>(sampler)];
  const std::string sp = ap + "/samplers/" + std::to_string(sampler);
  Curve c;
  if (s.interpolation == "LINEAR") c.interpolation = Interpolation::Linear;
  else if (s.interpolation == "STEP") c.interpolation = Interpolation::Step;
  else if (s.interpolation == "CUBICSPLINE") c.interpolation = Interpolation::CubicSpline;
  else fail(sp + "/interpolation", "must be LINEAR, STEP or CUBICSPLINE, got " + s.interpolation);
  // The input: float seconds, finite and strictly increasing (§3.11.2).
  if (s.input >= 0 && static_cast<std::size_t>(s.input) < m_.accessors.size() &&
      m_.accessors[static_cast<std::size_t>(s.input)].componentType != TINYGLTF_COMPONENT_TYPE_FLOAT)
    fail("/accessors/" + std::to_string(s.input) + "/componentType", "an animation's input must be FLOAT");
  c.times = resources_.read_floats(s.input, sp + "/input", {1});
  for (std::size_t k = 0; k < c.times.size(); ++k) {
    if (!std::isfinite(c.times[k]))
      fail("/accessors/" + std::to_string(s.input), "key time " + str(k) + " is not finite");
    if (k > 0 && !(c.times[k] > c.times[k - 1]))
      fail("/accessors/" + std::to_string(s.input), "key times must increase strictly: key " + str(k) + " (" +
                                                        std::to_string(c.times[k]) + ") follows " +
                                                        std::to_string(c.times[k - 1]));
  }
  int comps = 0;
  c.values = resources_.read_floats(s.output, sp + "/output", {weights ? 1 : static_cast<int>(width)}, &comps);
  c.width = width;
  const std::size_t per_key = (c.interpolation == Interpolation::CubicSpline ? 3 : 1) * width;
  if (c.values.size() != c.times.size() * per_key)
    fail(sp + "/output", "has " + str(c.values.size() / static_cast<std::size_t>(std::max(comps, 1))) +
                             " elements; " + str(c.times.size()) + " keys" +
                             (c.interpolation == Interpolation::CubicSpline ? " × 3 (CUBICSPLINE)" : "") +
                             (weights ? " × " + str(width) + " morph targets" : "") + " need " +
                             str(c.times.size() * per_key / (weights ? 1 : width)));
  for (float v : c.values)
    if (!std::isfinite(v)) fail("/accessors/" + std::to_string(s.output), "holds a value that is not finite");
  return c;
}

std::vector<AnimationSummary> Animations::summaries() const {
  std::vector<AnimationSummary> out;
  for (std::size_t i = 0; i < m_.animations.size(); ++i) {
    const tg::Animation& an = m_.animations[i];
    AnimationSummary a{an.name, 0.0, an.channels.size()};
    // The duration from each FLOAT SCALAR input's last key; an input that is not one is
    // left out here (it is an error only when the animation is applied: pose()).
    for (std::size_t s = 0; s < an.samplers.size(); ++s) {
      const int in = an.samplers[s].input;
      if (in < 0 || static_cast<std::size_t>(in) >= m_.accessors.size()) continue;
      const tg::Accessor& x = m_.accessors[static_cast<std::size_t>(in)];
      if (x.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT || x.type != TINYGLTF_TYPE_SCALAR) continue;
      const std::string sp = "/animations/" + str(i) + "/samplers/" + str(s);
      const std::vector<float> t = resources_.read_floats(in, sp + "/input", {1});
      if (!t.empty() && std::isfinite(t.back())) a.duration = std::max(a.duration, static_cast<double>(t.back()));
    }
    out.push_back(std::move(a));
  }
  return out;
}

std::vector<NodePose> Animations::pose() const {
  if (!options_.time && options_.animation.empty()) return {};
  const double t = options_.time.value_or(0.0);
  if (!std::isfinite(t)) fail("/animations", "the time must be finite");
  const int only = chosen();
  check_memory();
  std::vector<NodePose> pose(m_.nodes.size());
  for (std::size_t i = 0; i < m_.animations.size(); ++i) {
    if (only >= 0 && static_cast<std::size_t>(only) != i) continue;
    const tg::Animation& an = m_.animations[i];
    for (std::size_t k = 0; k < an.channels.size(); ++k) {
      const tg::AnimationChannel& ch = an.channels[k];
      const std::string cp = "/animations/" + str(i) + "/channels/" + str(k);
      if (ch.target_node < 0) {
        // KHR_animation_pointer and other extensions' targets: not applied.
        warn(cp + "/target: a channel without a target node is not applied");
        continue;
      }
      if (static_cast<std::size_t>(ch.target_node) >= m_.nodes.size())
        fail(cp + "/target/node", "node " + std::to_string(ch.target_node) + " does not exist");
      const auto node = static_cast<std::size_t>(ch.target_node);
      const std::string& path = ch.target_path;
      if (!m_.nodes[node].matrix.empty() && path != "weights")
        fail(cp + "/target/node", "node " + std::to_string(ch.target_node) +
                                      " has a matrix: an animation may only target nodes with TRS values");
      if (path == "translation" || path == "scale") {
        const Curve c = curve(i, ch.sampler, cp, 3, false);
        double v[3];
        sample(c, t, false, v);
        (path == "scale" ? pose[node].scale : pose[node].translation) = glm::dvec3(v[0], v[1], v[2]);
      } else if (path == "rotation") {
        const Curve c = curve(i, ch.sampler, cp, 4, false);
        double v[4];
        sample(c, t, true, v);
        pose[node].rotation = quat_at(v);
      } else if (path == "weights") {
        const std::size_t targets = morph_target_count(ch.target_node);
        if (targets == 0)
          fail(cp + "/target/node", "node " + std::to_string(ch.target_node) + " has no mesh with morph targets");
        const Curve c = curve(i, ch.sampler, cp, targets, true);
        std::vector<double> v(targets);
        sample(c, t, false, v.data());
        pose[node].weights = std::move(v);
      } else if (path == "pointer") {
        warn(cp + "/target/path: KHR_animation_pointer's targets are not applied");
      } else {
        fail(cp + "/target/path", "must be translation, rotation, scale or weights, got " + path);
      }
    }
  }
  return pose;
}

}  // namespace softpbr::pbr::gltf
