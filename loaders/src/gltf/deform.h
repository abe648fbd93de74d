// Morph targets and skins applied to a primitive's mesh on the CPU, before the renderer
// sees it (glTF 2.0 §3.7.2.2 and §3.7.3): the renderer then draws an ordinary Mesh.
// Matrices are made once per joint (in double, rounded to float once); each vertex is
// then computed alone in float, with the same operations in a fixed order, so the result
// has the same bits for any thread count. Private to the glTF reader (docs/design.md,
// "Animation and deformation").
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>

#include "softpbr/pbr/mesh.h"

namespace softpbr::raster {
class ThreadPool;
}

namespace softpbr::pbr::gltf {

// One morph target's deltas, three floats per accessor vertex (null: the target does not
// move that attribute; the floats are owned by the caller), and its weight.
struct MorphTarget {
  const float* position = nullptr;
  const float* normal = nullptr;
  const float* tangent = nullptr;
  double weight = 0.0;
};

// What one joint does to a vertex, made once per joint and pose (joint_palette): floats
// 0–11 the joint matrix J = world(joint) × inverseBindMatrix, its three rows of four;
// 12–20 its normal matrix, the inverse transpose of J's upper 3×3, three rows of three;
// 21–23 zero (24 floats: a vertex blends whole vectors of them).
using JointMatrix = std::array<float, 24>;
using JointPalette = std::vector<JointMatrix>;

// The palette of joint matrices `J` (by joint), each rounded to float once. A singular
// joint's normal matrix is its cofactor matrix (the normals of a flattened part keep a
// direction rather than becoming NaN); a joint at rest (J = I) gives the identity exactly.
JointPalette joint_palette(const std::vector<glm::dmat4>& J);

// A skinned primitive: per accessor vertex `influences` (joint, weight) pairs (4 per
// JOINTS_n/WEIGHTS_n set), and the palette of its skin's joints.
struct SkinInfluences {
  std::size_t influences = 0;
  std::vector<std::uint32_t> joints;
  std::vector<float> weights;  // normalised in double, then rounded: each vertex's sum is 1 (or exactly as given when it is)
  const JointPalette* palette = nullptr;
};

struct Deformation {
  std::vector<MorphTarget> targets;  // only those with a weight other than 0
  const SkinInfluences* skin = nullptr;
  const std::vector<std::uint32_t>* sources = nullptr;  // Mesh vertex → accessor vertex (null or empty: the same)
  bool flat = false;  // the normals are flat ones (made per triangle): made again from the morphed positions
};

// The mesh `base` deformed into `out`, which holds a copy of `base` (or an earlier
// deformation of it: only positions, normals and tangents' xyz are written; vertex count
// and streams must match base's). Per vertex, in float:
// morphed, p + w₁·Δp₁ + w₂·Δp₂ + … in the targets' order (normals and tangents alike),
// then skinned: the blend B = w₁·P₁ + w₂·P₂ + … of its joints' palette entries (in the
// order of its influences, weights of 0 skipped), p' = J_B·(p, 1), n' = N_B·n, t' = J_B·t
// (J_B and N_B: B's joint and normal matrices). Normals and tangents are not normalised here
// (the shading normalises them, as after any object transform), so weights 0 and joints at
// rest give `base` back bit for bit. Parallel over blocks of vertices on `pool` when given.
void deform(const Mesh& base, const Deformation& d, Mesh& out, raster::ThreadPool* pool);

// The same into a new mesh (a copy of base's indices, UVs and colours).
Mesh deform(const Mesh& base, const Deformation& d, raster::ThreadPool* pool);

// The inverse transpose of m's upper 3×3 (cofactors over the determinant): a joint's normal
// matrix. The identity gives the identity exactly; a singular matrix gives its cofactor
// matrix (the normals of a flattened part keep a direction rather than becoming NaN).
glm::dmat3 normal_matrix(const glm::dmat4& m);

}  // namespace softpbr::pbr::gltf
