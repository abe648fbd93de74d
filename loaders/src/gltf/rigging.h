// The glTF reader's skins and morph targets read and checked (glTF 2.0 §3.7.3 and
// §3.7.2.2): joint matrices from the joints' world transforms and inverse bind matrices,
// each primitive's JOINTS_n/WEIGHTS_n, the morph weights of a node and its targets' deltas,
// as deform.h applies them. Private to the glTF reader (docs/design.md, "Animation and
// deformation").
#pragma once

#include <cstddef>
#include <map>
#include <utility>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>

#include "gltf/deform.h"
#include "gltf/reader.h"
#include "gltf/resources.h"

namespace softpbr::pbr::gltf {

class Rigging : public Context {
 public:
  Rigging(const Context& context, const Resources& resources) : Context(context), resources_(resources) {}

  // Skin `skin`'s joint matrices, world(joint) × inverseBindMatrix, by joint; `world` and
  // `placed` are every node's world transform and whether the scene placed it (a joint
  // must be in the scene). `referrer`: the node's "skin".
  std::vector<glm::dmat4> joint_matrices(int skin, const std::vector<glm::dmat4>& world, const std::vector<bool>& placed,
                                         const std::string& referrer) const;

  // Primitive `p`'s influences (at `pointer`) for `vertices` accessor vertices and
  // `joints` joints: every JOINTS_n with its WEIGHTS_n, weights ≥ 0 with a sum above 0,
  // normalised to 1. Read once per primitive and joint count, kept for later poses (the
  // caller sets their palette).
  SkinInfluences& influences(const tg::Primitive& p, std::size_t vertices, std::size_t joints,
                             const std::string& pointer);

  // The morph weights of a node placing mesh `mesh`: its pose's (animated), else the
  // node's "weights", else the mesh's, else zeros; one per target of its primitives (which
  // must all have the same count).
  std::vector<double> weights(int node, int mesh, const std::vector<double>* posed) const;

  // Primitive `p`'s targets with a weight other than 0, their deltas read (`vertices`
  // each) once per target and kept for later poses.
  std::vector<MorphTarget> targets(const tg::Primitive& p, const std::vector<double>& weights, std::size_t vertices,
                                   const std::string& pointer);

 private:
  struct Deltas {
    std::vector<float> position, normal, tangent;
  };
  const Resources& resources_;
  std::map<std::pair<const tg::Primitive*, std::size_t>, SkinInfluences> influences_;  // by primitive and joint count
  std::map<std::pair<const tg::Primitive*, std::size_t>, Deltas> deltas_;              // by primitive and target
};

}  // namespace softpbr::pbr::gltf
