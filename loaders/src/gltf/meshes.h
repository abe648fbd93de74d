// The glTF reader's meshes: a primitive's attributes and indices (or its Draco data) as a
// Mesh, strips and fans as triangle lists, flat normals when it has none, MikkTSpace
// tangents when it is normal-mapped and has none; each made once, and once more with its
// winding reversed for a mirroring node. Private to the glTF reader (docs/design.md, "glTF").
#pragma once

#include <cstddef>
#include <map>
#include <memory>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "gltf/reader.h"
#include "gltf/resources.h"
#include "softpbr/pbr/mesh.h"

namespace softpbr::pbr::gltf {

class Meshes : public Context {
 public:
  // `draco_indices`: the Draco primitives' "indices", by (mesh, primitive), which the
  // pre-pass took out of the JSON (document.h).
  Meshes(const Context& context, const Resources& resources,
         std::map<std::pair<std::size_t, std::size_t>, int> draco_indices)
      : Context(context), resources_(resources), draco_indices_(std::move(draco_indices)) {}

  // A Draco primitive's indices accessor (which only describes the Draco data's triangles)
  // must exist.
  void check_draco_indices(std::size_t mesh, std::size_t k, const std::string& pointer) const;

  // A lower bound of the draw memory of one instance of mesh `index` (a valid index), from
  // its accessors' counts alone (nothing decoded): each primitive's triangles (of its
  // indices' or positions' count, by its mode) and its positions' count, as
  // object_draw_bytes counts them once the mesh is built.
  std::uint64_t draw_bytes_lower_bound(int index) const;

  // Primitive `k` of mesh `mesh` (at `pointer`), made once; `mirrored`: with each
  // triangle's winding reversed (a mirroring transform turns counter-clockwise triangles
  // clockwise on screen).
  std::shared_ptr<const Mesh> primitive(int mesh, std::size_t k, bool mirrored, const std::string& pointer,
                                        bool normal_mapped);

  // How primitive (mesh, k)'s Mesh, once made, maps to its accessors' vertices (for morph
  // targets and skins, deform.h): the accessor vertex of each Mesh vertex (empty: the
  // same index — flat normals and split tangents make others), and whether its normals
  // are flat ones made here (the primitive has no NORMAL).
  struct VertexSources {
    std::vector<std::uint32_t> sources;
    bool flat = false;
  };
  const VertexSources& vertex_sources(int mesh, std::size_t k) const;

 private:
  // `draco_indices`: a Draco primitive's indices accessor (-1: none).
  std::shared_ptr<const Mesh> primitive_mesh(const tg::Primitive& p, const std::string& pointer, bool normal_mapped,
                                             int draco_indices);
  std::vector<std::uint32_t> triangles(int mode, const std::vector<std::uint32_t>& v) const;
  static void flat_normals(Mesh& mesh);
  static const VertexSources no_sources_;

  const Resources& resources_;
  std::map<std::pair<std::size_t, std::size_t>, int> draco_indices_;
  std::map<std::tuple<int, std::size_t, bool>, std::shared_ptr<const Mesh>> meshes_;
  std::map<const Mesh*, VertexSources> sources_;  // by the unmirrored Mesh, when not the identity
};

}  // namespace softpbr::pbr::gltf
