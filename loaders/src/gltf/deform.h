// Morph targets and skins applied to a primitive's mesh on the CPU, before the renderer
// sees it (glTF 2.0 §3.7.2.2 and §3.7.3): the renderer then draws an ordinary Mesh.
// Each vertex is computed alone, in double, in a fixed order, so the result has the same
// bits for any thread count. Private to the glTF reader (docs/design.md, "Animation and
// deformation").
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/mat4x4.hpp>

#include "softpbr/pbr/mesh.h"

namespace softpbr::raster {
class ThreadPool;
}

namespace softpbr::pbr::gltf {

// One morph target's deltas, three floats per accessor vertex (empty: the target does not
// move that attribute), and its weight.
struct MorphTarget {
  std::vector<float> position, normal, tangent;
  double weight = 0.0;
};

// A skinned primitive: per accessor vertex `influences` (joint, weight) pairs (4 per
// JOINTS_n/WEIGHTS_n set), and the joint matrices (world of the joint × its inverse bind
// matrix) by joint.
struct SkinInfluences {
  std::size_t influences = 0;
  std::vector<std::uint32_t> joints;
  std::vector<double> weights;  // normalised: each vertex's sum is 1 (or exactly as given when it is)
  const std::vector<glm::dmat4>* matrices = nullptr;
};

struct Deformation {
  std::vector<MorphTarget> targets;  // only those with a weight other than 0
  const SkinInfluences* skin = nullptr;
  const std::vector<std::uint32_t>* sources = nullptr;  // Mesh vertex → accessor vertex (null or empty: the same)
  bool flat = false;  // the normals are flat ones (made per triangle): made again from the morphed positions
};

// The mesh `base` deformed: positions, normals and tangents (xyz) morphed,
// p + Σ wᵢ·Δpᵢ, then skinned, M·p with M = Σ wⱼ·Jⱼ, normals by M's inverse transpose and
// tangents by M. Normals and tangents are not normalised here (the shading normalises
// them, as after any object transform), so weights 0 and joint matrices at identity give
// `base` back bit for bit. Indices, UVs and colours are copied. Parallel over ranges of
// vertices on `pool` when given.
Mesh deform(const Mesh& base, const Deformation& d, raster::ThreadPool* pool);

}  // namespace softpbr::pbr::gltf
