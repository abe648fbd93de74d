// A synthetic skinned and morphed mesh for gltf::deform's test (test_gltf_animation.cpp)
// and benchmark (benchmarks/bench_deform.cpp): a grid of `vertices` vertices with normals
// (and, when asked, tangents and a vertex → accessor map that reverses the order), four
// influences per vertex over `joints` joints (weights from an integer hash, normalised),
// joints turned and moved by a fixed recipe, and one morph target moving positions and
// normals (weight 0.5). Everything from integers: the same mesh on every machine.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "gltf/deform.h"

namespace softpbr::testing {

struct SyntheticRig {
  pbr::Mesh base;
  std::vector<std::uint32_t> sources;
  std::vector<glm::dmat4> joint_matrices;  // by joint, in double (the palette's source)
  pbr::gltf::JointPalette palette;
  pbr::gltf::SkinInfluences skin;
  std::vector<float> delta_position, delta_normal, delta_tangent;  // the target's
  pbr::gltf::Deformation deformation;  // refers to the above: a rig is not moved
};

inline std::unique_ptr<SyntheticRig> synthetic_rig(std::size_t vertices, std::size_t joints, bool tangents,
                                                   bool reversed_sources) {
  auto rig = std::make_unique<SyntheticRig>();
  std::uint32_t h = 12345u;
  auto next = [&h] {  // xorshift32
    h ^= h << 13, h ^= h >> 17, h ^= h << 5;
    return h;
  };
  auto unit = [&] { return static_cast<float>(next() >> 8) * (1.0f / 16777216.0f); };  // [0, 1), exact
  const std::size_t side = 1024;
  pbr::Mesh& m = rig->base;
  m.vertices.resize(vertices);
  if (tangents) m.tangents.resize(vertices);
  for (std::size_t i = 0; i < vertices; ++i) {
    const float x = static_cast<float>(i % side) / 64.0f, y = static_cast<float>(i / side) / 64.0f;
    m.vertices[i] = {{x, y, unit() - 0.5f}, {unit() - 0.5f, unit() - 0.5f, 1.0f}, {x, y}};
    if (tangents) m.tangents[i] = {1.0f, 0.0f, unit() - 0.5f, (i & 1) != 0 ? -1.0f : 1.0f};
  }
  for (std::size_t i = 0; i + 2 < vertices; i += 3)
    m.indices.insert(m.indices.end(), {static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(i + 1),
                                       static_cast<std::uint32_t>(i + 2)});
  if (reversed_sources)
    for (std::size_t i = 0; i < vertices; ++i) rig->sources.push_back(static_cast<std::uint32_t>(vertices - 1 - i));
  std::vector<glm::dmat4> J(joints);
  for (std::size_t j = 0; j < joints; ++j) {
    const double a = 0.1 * static_cast<double>(j % 17), b = 0.05 * static_cast<double>(j % 5);
    J[j] = glm::translate(glm::dmat4(1.0), glm::dvec3(0.01 * static_cast<double>(j), 0.5, -0.25)) *
           glm::rotate(glm::dmat4(1.0), a, glm::dvec3(0.0, 0.0, 1.0)) *
           glm::rotate(glm::dmat4(1.0), b, glm::dvec3(1.0, 0.0, 0.0)) *
           glm::scale(glm::dmat4(1.0), glm::dvec3(1.0 + 0.01 * static_cast<double>(j % 3)));
  }
  rig->palette = pbr::gltf::joint_palette(J);
  rig->joint_matrices = J;
  pbr::gltf::SkinInfluences& k = rig->skin;
  k.influences = 4;
  k.joints.resize(4 * vertices);
  k.weights.resize(4 * vertices);
  for (std::size_t v = 0; v < vertices; ++v) {
    float w[4], sum = 0.0f;
    for (std::size_t c = 0; c < 4; ++c) {
      k.joints[4 * v + c] = next() % static_cast<std::uint32_t>(joints);
      w[c] = c == 3 && (v % 4) == 0 ? 0.0f : unit() + 0.0625f;  // every fourth vertex: three influences
      sum += w[c];
    }
    for (std::size_t c = 0; c < 4; ++c) k.weights[4 * v + c] = w[c] / sum;
  }
  k.palette = &rig->palette;
  rig->delta_position.resize(3 * vertices);
  rig->delta_normal.resize(3 * vertices);
  for (float& x : rig->delta_position) x = unit() - 0.5f;
  for (float& x : rig->delta_normal) x = 0.25f * (unit() - 0.5f);
  pbr::gltf::MorphTarget t;
  t.weight = 0.5;
  t.position = rig->delta_position.data();
  t.normal = rig->delta_normal.data();
  if (tangents) {
    rig->delta_tangent.resize(3 * vertices);
    for (float& x : rig->delta_tangent) x = 0.25f * (unit() - 0.5f);
    t.tangent = rig->delta_tangent.data();
  }
  rig->deformation.targets.push_back(t);
  rig->deformation.skin = &rig->skin;
  rig->deformation.sources = &rig->sources;
  return rig;
}

}  // namespace softpbr::testing
