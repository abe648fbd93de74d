// The glTF reader's scene graph (as Filament's gltfio's AssetLoader): the required
// extensions, the scene, its node hierarchy with transforms composed in double, and what
// the nodes place — mesh primitives (meshes.h) with their materials (materials.h),
// cameras, KHR_lights_punctual lights — into the GltfScene. Private to the glTF reader
// (docs/design.md, "glTF").
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <glm/mat4x4.hpp>

#include "gltf/animation.h"
#include "gltf/materials.h"
#include "gltf/meshes.h"
#include "gltf/reader.h"
#include "gltf/resources.h"
#include "gltf/rigging.h"

namespace softpbr::pbr::gltf {

// EXT_mesh_gpu_instancing: a node's mesh drawn once per instance (SceneGraph::instance_worlds).
inline constexpr const char* kInstancing = "EXT_mesh_gpu_instancing";

class SceneGraph : public Context {
 public:
  // `fallback` and `draco_indices`: what the pre-pass took out of the JSON (document.h).
  SceneGraph(const Context& context, std::string base_dir, std::map<int, std::uint64_t> fallback,
             std::map<std::pair<std::size_t, std::size_t>, int> draco_indices)
      : Context(context),
        resources_(context, std::move(base_dir), std::move(fallback)),
        materials_(context),
        meshes_(context, resources_, std::move(draco_indices)),
        animations_(context, resources_),
        rigging_(context, resources_) {}

  // Fills the GltfScene: the compressed views decoded, the scene's nodes visited, then
  // the textures made and the objects placed.
  void load();

  // After load(): the GltfScene's objects, cameras and lights made again for the pose
  // options_'s time and animation now name (the same steps as load()'s, with what it read
  // and made kept: meshes, materials and textures, skins' influences, targets' deltas).
  void pose();

 private:
  void place();  // the pose sampled, the nodes visited, the meshes deformed
  void check_extensions() const;
  int pick_scene() const;
  void check_draw_memory(const std::vector<int>& roots, const std::string& where) const;
  glm::dmat4 local_matrix(std::size_t index, const std::string& pointer) const;
  void visit(int index, const glm::dmat4& parent, const std::string& referrer, int depth, std::vector<bool>& on_path);
  void add_mesh(int index, const glm::dmat4& world, const std::string& referrer, std::size_t node);
  // EXT_mesh_gpu_instancing: the node's extension's attributes (null: none), its instances
  // as counted before anything is read (1 without the extension), and their world matrices.
  const tg::Value* instancing(std::size_t node) const;
  std::uint64_t instance_count(std::size_t node) const;
  std::vector<glm::dmat4> instance_worlds(std::size_t node, const glm::dmat4& world) const;
  void deform_meshes();
  void add_camera(int index, const glm::dmat4& world, const std::string& referrer);
  void add_light(int index, const glm::dmat4& world, const std::string& referrer);

  Resources resources_;
  Materials materials_;
  Meshes meshes_;
  Animations animations_;
  Rigging rigging_;
  std::vector<int> roots_;      // the scene's root nodes
  std::string where_;           // their JSON pointer ("/scenes/0/nodes")
  std::vector<NodePose> pose_;   // by node, at the chosen moment (empty: no animation applied)
  std::vector<glm::dmat4> world_;  // by node, once visited
  std::vector<bool> visited_;      // by node: placed by the scene
  struct Placed {
    std::shared_ptr<const Mesh> mesh;
    int material;
    glm::mat4 transform;
    // A skinned or morphed primitive, deformed once every node's world is known
    // (deform_meshes): its node (−1: none), mesh and primitive.
    int node = -1;
    int mesh_index = -1;
    std::size_t primitive = 0;
    std::vector<double> weights{};
    bool skinned = false;
  };
  std::vector<Placed> placed_;
};

}  // namespace softpbr::pbr::gltf
